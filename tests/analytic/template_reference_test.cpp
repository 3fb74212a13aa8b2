// Particle templates against the reference values of docs/physics.md section 1.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "bushel/core/input_error.hpp"
#include "bushel/particles/material.hpp"
#include "bushel/particles/template_library.hpp"

namespace bushel {
namespace {

struct Reference {
  const char* name;
  double volume;  // [m3]
};

TEST(TemplateReference, UnionVolumesWithinOnePercent) {
  const Reference refs[] = {
      {"large_5s", 2.52e-8}, {"medium_5s", 1.79e-8}, {"small_5s", 1.17e-8}, {"large_asg", 2.64e-8}};
  for (const auto& r : refs) {
    const ParticleTemplate& t = TemplateLibrary::builtin().get(r.name);
    EXPECT_NEAR(t.volume / r.volume, 1.0, 0.01) << r.name;
  }
}

TEST(TemplateReference, Large5sMassAtWheatDensity) {
  // docs/physics.md: m = 0.0346 g at 1373 kg/m3.
  const double mass = TemplateLibrary::builtin().get("large_5s").mass(materials::wheat().density);
  EXPECT_NEAR(mass / 0.0346e-3, 1.0, 0.01);
}

TEST(TemplateReference, VolumeConvergesWithResolution) {
  // The default resolution sits within 0.01% of a resolution four times finer.
  const std::string csv = std::string(BUSHEL_DATA_DIR) + "/wheat_clumps.csv";
  const TemplateLibrary coarse = TemplateLibrary::read_csv(csv, {100});
  const TemplateLibrary normal = TemplateLibrary::read_csv(csv, {400});
  const TemplateLibrary fine = TemplateLibrary::read_csv(csv, {1600});
  for (const auto& name : fine.names()) {
    const double v = fine.get(name).volume;
    const double e_coarse = std::abs(coarse.get(name).volume - v) / v;
    const double e_normal = std::abs(normal.get(name).volume - v) / v;
    EXPECT_LT(e_normal, 1e-4) << name;
    EXPECT_LE(e_normal, e_coarse) << name;
  }
}

TEST(TemplateReference, AxialClumpsKeepTheirAxisAndCentre) {
  // The 5- and 7-sphere clumps lie along x and are symmetric about the origin, so the
  // principal frame is the input frame and the centre of mass is at the origin.
  const ParticleTemplate& t = TemplateLibrary::builtin().get("large_5s");
  EXPECT_NEAR(norm(t.input_centroid), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(t.principal_to_input.w), 1.0, 1e-9);
  EXPECT_NEAR(t.spheres[0].centre.x, -2.149e-3, 1e-12);
  EXPECT_NEAR(t.extents().x, 6.12e-3, 1e-12);
  EXPECT_NEAR(t.extents().y, 3.05e-3, 1e-12);
  EXPECT_NEAR(t.aspect_ratio(), 6.12 / 3.05, 1e-9);
  EXPECT_DOUBLE_EQ(t.min_sphere_radius(), 0.911e-3);
  // Axisymmetric: the two transverse moments agree, the axial one is smallest.
  EXPECT_NEAR(t.principal_moments.y / t.principal_moments.z, 1.0, 1e-6);
  EXPECT_LT(t.principal_moments.x, t.principal_moments.y);
}

TEST(TemplateReference, PrincipalFrameDiagonalisesIrregularClumps) {
  // For the X-ray fitted clumps, integrate the re-expressed spheres again: the centroid is
  // at the origin and the frame is already principal, up to the integration error of a grid
  // that now lies differently across the clump (about 1e-5, see VolumeConvergesWithResolution).
  for (const char* name : {"large_asg", "medium_asg", "small_asg"}) {
    const ParticleTemplate& t = TemplateLibrary::builtin().get(name);
    const ParticleTemplate again = make_template("again", t.spheres);
    EXPECT_LT(norm(again.input_centroid), 2e-5 * t.bounding_radius()) << name;
    EXPECT_NEAR(std::abs(again.principal_to_input.w), 1.0, 1e-5) << name;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(again.principal_moments[i] / t.principal_moments[i], 1.0, 1e-4) << name;
    EXPECT_LE(t.principal_moments.x, t.principal_moments.y);
    EXPECT_LE(t.principal_moments.y, t.principal_moments.z);
  }
}

TEST(TemplateReference, RotatedInputGivesTheSameTemplate) {
  const ParticleTemplate& t = TemplateLibrary::builtin().get("medium_asg");
  const Quat q = normalized(Quat{0.3, -0.5, 0.2, 0.8});
  std::vector<SphereElement> moved;
  for (const auto& s : t.spheres) moved.push_back({rotate(q, s.centre) + Vec3{1e-3, -2e-3, 0.5e-3}, s.radius});
  const ParticleTemplate u = make_template("moved", moved);
  EXPECT_NEAR(u.volume / t.volume, 1.0, 1e-4);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(u.principal_moments[i] / t.principal_moments[i], 1.0, 5e-4);
  // principal_to_input maps the stored spheres back to where they were given.
  for (std::size_t i = 0; i < moved.size(); ++i) {
    const Vec3 back = rotate(u.principal_to_input, u.spheres[i].centre) + u.input_centroid;
    EXPECT_NEAR(norm(back - moved[i].centre), 0.0, 1e-12);
  }
}

TEST(TemplateReference, SingleSphereIsExact) {
  const ParticleTemplate t = make_template("ball", {{{1, 2, 3}, 0.5e-3}});
  EXPECT_DOUBLE_EQ(t.volume, 4.0 / 3.0 * std::numbers::pi * 0.125e-9);
  EXPECT_DOUBLE_EQ(t.principal_moments.x, 0.4 * t.volume * 0.25e-6);
  EXPECT_EQ(t.spheres[0].centre, (Vec3{0, 0, 0}));
  EXPECT_DOUBLE_EQ(t.aspect_ratio(), 1.0);
}

TEST(TemplateReference, LibraryErrors) {
  try {
    TemplateLibrary::builtin().get("large_5");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'large_5s'"), std::string::npos) << e.what();
  }
  try {
    TemplateLibrary::parse_csv("template,sphere,x_mm,y_mm,z_mm,radius_mm\na,s0,0,0,0,1\na,s1,1,0,0,-2\n", "u.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "u.csv:3: key 'radius_mm': expected a positive radius in mm, got -2");
  }
  const TemplateLibrary m =
      TemplateLibrary::parse_csv("template,sphere,x_m,y_m,z_m,radius_m\nb,s0,0,0,0,0.001\n", "m.csv");
  EXPECT_DOUBLE_EQ(m.get("b").spheres[0].radius, 0.001);
  EXPECT_THROW(resolve_template("/nonexistent/dir/templates.csv"), InputError);
  EXPECT_THROW(resolve_template(std::string(BUSHEL_DATA_DIR) + "/wheat_clumps.csv"), InputError);  // several
  EXPECT_EQ(resolve_template(std::string(BUSHEL_DATA_DIR) + "/wheat_clumps.csv:small_7s").spheres.size(), 7u);
}

}  // namespace
}  // namespace bushel
