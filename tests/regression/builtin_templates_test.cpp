// Mass properties of every built-in template against committed reference output
// (tests/regression/data/builtin_templates.csv, written by `bushel particle --list --csv`).
// A change here means the integration or the shipped data changed: regenerate the file
// only when that change is intended, and say why in the commit.
#include <gtest/gtest.h>

#include "bushel/contact/time_scales.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/particles/material.hpp"
#include "bushel/particles/template_library.hpp"

namespace bushel {
namespace {

TEST(BuiltinTemplates, MatchCommittedReference) {
  const io::CsvTable ref =
      io::CsvTable::read(std::string(BUSHEL_TEST_DATA_DIR) + "/regression/data/builtin_templates.csv");
  const auto& lib = TemplateLibrary::builtin();
  ASSERT_EQ(ref.rows().size(), lib.names().size());
  const Material w = materials::wheat();
  constexpr double tol = 1e-7;  // relative: the integration is deterministic, this only absorbs printing
  for (const auto& row : ref.rows()) {
    const std::string& name = row.fields[ref.column("template")];
    const ParticleTemplate& t = lib.get(name);
    auto expect = [&](const char* column, double actual) {
      const double expected = ref.number(row, ref.column(column));
      EXPECT_NEAR(actual, expected, tol * std::abs(expected)) << name << " " << column;
    };
    expect("spheres", static_cast<double>(t.spheres.size()));
    expect("volume_m3", t.volume);
    expect("mass_kg", t.mass(w.density));
    expect("equivalent_diameter_m", t.equivalent_diameter());
    expect("aspect_ratio", t.aspect_ratio());
    const Vec3 inertia = t.principal_inertia(w.density);
    expect("inertia_x_kg_m2", inertia.x);
    expect("inertia_y_kg_m2", inertia.y);
    expect("inertia_z_kg_m2", inertia.z);
    expect("rayleigh_time_step_s",
           rayleigh_time_step(t.min_sphere_radius(), w.density, w.shear_modulus, w.poisson_ratio));
  }
}

}  // namespace
}  // namespace bushel
