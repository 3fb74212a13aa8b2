// The particle store: what a type's bodies share (moments, element centres) is kept once per
// type and follows each body through a reordering; checkpoints round-trip, version 1 (with
// per-body moments and per-element centres) still loads, and a checkpoint whose particles do
// not match the scenario's types is refused.
#include <gtest/gtest.h>

#include <random>

#include "bushel/core/input_error.hpp"
#include "bushel/io/binary_archive.hpp"
#include "bushel/particles/material.hpp"
#include "bushel/particles/particle_system.hpp"
#include "bushel/particles/template_library.hpp"

namespace bushel {
namespace {

ParticleType type_of(ParticleTemplate shape, double density = 1373.0) {
  Material m = materials::wheat();
  m.density = density;
  return {shape.name, std::move(shape), m};
}

// A sphere type, a 5-sphere clump type and 12 bodies of both, in random poses.
ParticleSystem mixed(double clump_density = 1373.0) {
  ParticleSystem ps;
  ps.add_type(type_of(make_template("sphere", {SphereElement{{}, 2e-3}})));
  ps.add_type(type_of(TemplateLibrary::builtin().get("large_5s"), clump_density));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 12; ++k) {
    const Quat q = normalized(Quat{u(rng), u(rng), u(rng), u(rng)});
    ps.add(k % 3 == 0 ? 0 : 1, {.position = Vec3{u(rng), u(rng), u(rng)} * 0.01,
                                .orientation = q,
                                .velocity = Vec3{u(rng), u(rng), u(rng)},
                                .angular_velocity = Vec3{u(rng), u(rng), u(rng)} * 10.0});
  }
  return ps;
}

// The checkpoint bytes of version 1: the same fields, with each body's moments and inverse
// moments (`moments`, the inverses derived) after the masses and each element's centre after
// the species.
std::string version_1_bytes(const ParticleSystem& ps, const std::vector<Vec3>& moments) {
  io::BinaryWriter v2;
  ps.save(v2);
  io::BinaryReader head(v2.bytes(), "version 2");
  io::BinaryWriter v;
  v.put(head.get<std::uint64_t>());  // the type count and the next ids
  v.put(head.get<std::uint32_t>());
  v.put(head.get<std::uint32_t>());
  v.put(ps.body_id), v.put(ps.body_type), v.put(ps.position), v.put(ps.orientation), v.put(ps.velocity);
  v.put(ps.angular_velocity), v.put(ps.angular_momentum), v.put(ps.force), v.put(ps.torque);
  v.put(ps.rolling_resistance), v.put(ps.mass);
  std::vector<Vec3> inverse, centres;
  for (const Vec3& i : moments) inverse.push_back({1.0 / i.x, 1.0 / i.y, 1.0 / i.z});
  v.put(moments), v.put(inverse);
  v.put(ps.first_sphere), v.put(ps.sphere_count), v.put(ps.sphere_id), v.put(ps.owner), v.put(ps.species);
  for (std::size_t b = 0; b < ps.bodies(); ++b)
    centres.insert(centres.end(), ps.offsets(b).begin(), ps.offsets(b).end());
  v.put(centres);
  v.put(ps.radius), v.put(ps.sphere_position);
  return v.bytes();
}

std::vector<Vec3> moments_of(const ParticleSystem& ps) {
  std::vector<Vec3> m;
  for (std::size_t b = 0; b < ps.bodies(); ++b) m.push_back(ps.inertia(b));
  return m;
}

void expect_same_state(const ParticleSystem& a, const ParticleSystem& b) {
  EXPECT_EQ(a.body_id, b.body_id);
  EXPECT_EQ(a.body_type, b.body_type);
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.angular_momentum, b.angular_momentum);
  EXPECT_EQ(a.mass, b.mass);
  EXPECT_EQ(a.first_sphere, b.first_sphere);
  EXPECT_EQ(a.species, b.species);
  EXPECT_EQ(a.sphere_position, b.sphere_position);
  EXPECT_EQ(moments_of(a), moments_of(b));
}

TEST(ParticleSystem, BodiesShareTheirTypesMomentsAndCentres) {
  ParticleSystem ps = mixed();
  const ParticleTemplate& clump = ps.types()[1].shape;
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    const ParticleType& t = ps.types()[ps.body_type[b]];
    EXPECT_EQ(ps.inertia(b), t.shape.principal_inertia(t.material.density));
    EXPECT_EQ(ps.inverse_inertia(b).x, 1.0 / ps.inertia(b).x);
    ASSERT_EQ(ps.offsets(b).size(), t.shape.spheres.size());
    for (std::size_t k = 0; k < t.shape.spheres.size(); ++k) EXPECT_EQ(ps.offsets(b)[k], t.shape.spheres[k].centre);
  }
  // Reversed, each body keeps its type's moments and centres, and its elements sit where the
  // centres and its pose put them.
  std::vector<std::uint32_t> order;
  for (std::size_t b = ps.bodies(); b-- > 0;) order.push_back(static_cast<std::uint32_t>(b));
  ps.permute(order);
  ASSERT_EQ(ps.body_type[0], 1u);  // body 11 of 12 (11 % 3 != 0) is a clump
  ps.update_sphere_positions();
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    for (std::uint32_t k = 0; k < ps.sphere_count[b]; ++k) {
      const Vec3 expected = ps.position[b] + rotate(ps.orientation[b], ps.offsets(b)[k]);
      EXPECT_NEAR(norm(ps.sphere_position[ps.first_sphere[b] + k] - expected), 0.0, 1e-15);
    }
  }
  EXPECT_EQ(ps.offsets(0).data(), ps.offsets(1).data());  // one table per type
  EXPECT_EQ(ps.offsets(0).size(), clump.spheres.size());
}

TEST(ParticleSystem, CheckpointsOfBothVersionsLoad) {
  const ParticleSystem ps = mixed();
  io::BinaryWriter out;
  ps.save(out);
  ParticleSystem back = mixed();
  back.permute(std::vector<std::uint32_t>{3, 1});  // (loading replaces every body)
  io::BinaryReader in(out.bytes(), "version 2");
  back.load(in, 2);
  EXPECT_TRUE(in.done());
  expect_same_state(back, ps);

  const std::string v1 = version_1_bytes(ps, moments_of(ps));
  ParticleSystem old = mixed();
  io::BinaryReader in1(v1, "version 1");
  old.load(in1, 1);
  EXPECT_TRUE(in1.done());
  expect_same_state(old, ps);
}

// A version-1 checkpoint whose bodies had other moments, or one of either version whose
// bodies have another mass (a scenario whose density changed since), is refused by name.
TEST(ParticleSystem, ACheckpointOfOtherShapesIsRefused) {
  const ParticleSystem ps = mixed();
  std::vector<Vec3> moments = moments_of(ps);
  moments[4].y *= 1.0 + 1e-12;
  ParticleSystem old = mixed();
  const std::string v1 = version_1_bytes(ps, moments);  // (the reader views it)
  io::BinaryReader in1(v1, "version 1");
  try {
    old.load(in1, 1);
    FAIL() << "loaded a checkpoint of other moments";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("other shapes or densities"), std::string::npos) << e.what();
  }
  io::BinaryWriter out;
  ps.save(out);
  ParticleSystem denser = mixed(1400.0);
  io::BinaryReader in(out.bytes(), "version 2");
  EXPECT_THROW(denser.load(in, 2), InputError);
}

}  // namespace
}  // namespace bushel
