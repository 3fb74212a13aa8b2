// The particle store: what a type's bodies share (moments, element centres) is kept once per
// type and follows each body through a reordering; checkpoints round-trip, versions 1 (with
// per-body moments and per-element centres) and 2 (with per-body masses and last forces)
// still load, and a checkpoint whose particles do not match the scenario's types is refused.
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

// The last forces that checkpoints of versions 1 and 2 held per body (made up).
ParticleSystem::SavedForces made_up_forces(std::size_t bodies) {
  ParticleSystem::SavedForces f;
  for (std::size_t b = 0; b < bodies; ++b) {
    const auto x = static_cast<double>(b);
    f.force.push_back({x, 2.0 * x, -x});
    f.torque.push_back({-x, 0.5, x});
    f.rolling_resistance.push_back(0.1 * x);
  }
  return f;
}

// The checkpoint bytes of version 2, or of version 1 (with each body's moments `moments`, and
// their inverses, after the masses and each element's centre after the species): each body's
// last forces (made_up_forces) and mass after its angular momentum, not its type's masses.
std::string old_version_bytes(const ParticleSystem& ps, int version, const std::vector<Vec3>& moments = {}) {
  io::BinaryWriter v3;
  ps.save(v3);
  io::BinaryReader head(v3.bytes(), "version 3");
  io::BinaryWriter v;
  v.put(head.get<std::uint64_t>());  // the type count and the next ids
  v.put(head.get<std::uint32_t>());
  v.put(head.get<std::uint32_t>());
  v.put(ps.body_id), v.put(ps.body_type), v.put(ps.position), v.put(ps.orientation), v.put(ps.velocity);
  v.put(ps.angular_velocity), v.put(ps.angular_momentum);
  const ParticleSystem::SavedForces f = made_up_forces(ps.bodies());
  v.put(f.force), v.put(f.torque), v.put(f.rolling_resistance);
  std::vector<double> masses;
  for (std::size_t b = 0; b < ps.bodies(); ++b) masses.push_back(ps.mass(b));
  v.put(masses);
  if (version == 1) {
    std::vector<Vec3> inverse;
    for (const Vec3& i : moments) inverse.push_back({1.0 / i.x, 1.0 / i.y, 1.0 / i.z});
    v.put(moments), v.put(inverse);
  }
  v.put(ps.first_sphere), v.put(ps.sphere_count), v.put(ps.sphere_id), v.put(ps.owner), v.put(ps.species);
  if (version == 1) {
    std::vector<Vec3> centres;
    for (std::size_t b = 0; b < ps.bodies(); ++b)
      centres.insert(centres.end(), ps.offsets(b).begin(), ps.offsets(b).end());
    v.put(centres);
  }
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
  for (std::size_t k = 0; k < a.bodies() && k < b.bodies(); ++k) EXPECT_EQ(a.mass(k), b.mass(k));
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
      const Vec3 expected = ps.position[b] + rotate(ps.orientation_of(b), ps.offsets(b)[k]);
      EXPECT_NEAR(norm(ps.sphere_position[ps.first_sphere[b] + k] - expected), 0.0, 1e-15);
    }
  }
  EXPECT_EQ(ps.offsets(0).data(), ps.offsets(1).data());  // one table per type
  EXPECT_EQ(ps.offsets(0).size(), clump.spheres.size());
}

void expect_forces(const ParticleSystem::SavedForces& a, const ParticleSystem::SavedForces& b) {
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(a.torque, b.torque);
  EXPECT_EQ(a.rolling_resistance, b.rolling_resistance);
}

// Lone spheres alone keep no orientation and no angular momentum: they read as identity and
// I omega, a checkpoint holds those (the same section as with them kept) and loads back, and
// a clump type registered later keeps them from then on, starting from those values.
TEST(ParticleSystem, LoneSpheresKeepNoRotationUntilAClumpTypeComes) {
  ParticleSystem ps;
  ps.add_type(type_of(make_template("sphere", {SphereElement{{}, 2e-3}})));
  const Quat turned = normalized(Quat{0.3, -0.5, 0.2, 0.7});
  for (int k = 0; k < 3; ++k) {
    ps.add(0, {.position = Vec3{0.01 * k, 0.0, 0.0},
               .orientation = turned,
               .velocity = {},
               .angular_velocity = Vec3{1.0, -2.0, 3.0 * k}});
  }
  EXPECT_FALSE(ps.keeps_rotation());
  EXPECT_TRUE(ps.orientation.empty() && ps.angular_momentum.empty());
  const double i = ps.inertia(0).x;
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    EXPECT_EQ(ps.orientation_of(b), Quat{});
    EXPECT_EQ(ps.angular_momentum_of(b), i * ps.angular_velocity[b]);
    EXPECT_EQ(ps.sphere_position[b], ps.position[b]);
  }
  EXPECT_DOUBLE_EQ(ps.kinetic_energy(), 0.5 * i * (5.0 + 14.0 + 41.0));  // (at rest: spin alone)
  io::BinaryWriter out;
  ps.save(out);
  io::BinaryReader in(out.bytes(), "spheres");
  in.get<std::uint64_t>(), in.get<std::uint32_t>(), in.get<std::uint32_t>();
  in.get<std::vector<std::uint32_t>>(), in.get<std::vector<std::uint32_t>>(), in.get<std::vector<Vec3>>();
  EXPECT_EQ(in.get<std::vector<Quat>>(), std::vector<Quat>(3, Quat{}));
  in.get<std::vector<Vec3>>(), in.get<std::vector<Vec3>>();
  EXPECT_EQ(in.get<std::vector<Vec3>>()[2], ps.angular_momentum_of(2));
  ParticleSystem back;
  back.add_type(type_of(make_template("sphere", {SphereElement{{}, 2e-3}})));
  io::BinaryReader again(out.bytes(), "spheres");
  back.load(again, 3);
  EXPECT_FALSE(back.keeps_rotation());
  EXPECT_TRUE(back.orientation.empty() && back.angular_momentum.empty());
  EXPECT_EQ(back.angular_velocity, ps.angular_velocity);
  EXPECT_EQ(back.position, ps.position);
  ps.add_type(type_of(TemplateLibrary::builtin().get("large_5s")));
  ASSERT_TRUE(ps.keeps_rotation());
  ps.add(1, {.position = {}, .orientation = turned, .velocity = {}, .angular_velocity = Vec3{0.0, 0.0, 1.0}});
  ASSERT_EQ(ps.orientation.size(), 4u);
  ASSERT_EQ(ps.angular_momentum.size(), 4u);
  EXPECT_EQ(ps.orientation[1], Quat{});
  EXPECT_EQ(ps.angular_momentum[2], i * ps.angular_velocity[2]);
  EXPECT_EQ(ps.orientation[3], turned);
  EXPECT_EQ(ps.angular_momentum_of(3), ps.spin_momentum(3));
}

TEST(ParticleSystem, CheckpointsOfEveryVersionLoad) {
  const ParticleSystem ps = mixed();
  io::BinaryWriter out;
  ps.save(out);
  ParticleSystem back = mixed();
  back.permute(std::vector<std::uint32_t>{3, 1});  // (loading replaces every body)
  io::BinaryReader in(out.bytes(), "version 3");
  expect_forces(back.load(in, 3), {});  // (the engine keeps them with its contact sums)
  EXPECT_TRUE(in.done());
  expect_same_state(back, ps);

  for (const int version : {1, 2}) {
    const std::string bytes = old_version_bytes(ps, version, moments_of(ps));
    ParticleSystem old = mixed();
    io::BinaryReader in_old(bytes, "version " + std::to_string(version));
    expect_forces(old.load(in_old, static_cast<std::uint32_t>(version)), made_up_forces(ps.bodies()));
    EXPECT_TRUE(in_old.done());
    expect_same_state(old, ps);
  }
}

// A version-1 checkpoint whose bodies had other moments, or one of version 2 or 3 whose
// bodies have another mass (a scenario whose density changed since), is refused by name.
TEST(ParticleSystem, ACheckpointOfOtherShapesIsRefused) {
  const ParticleSystem ps = mixed();
  std::vector<Vec3> moments = moments_of(ps);
  moments[4].y *= 1.0 + 1e-12;
  ParticleSystem old = mixed();
  const std::string v1 = old_version_bytes(ps, 1, moments);  // (the reader views it)
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
  io::BinaryReader in(out.bytes(), "version 3");
  EXPECT_THROW(denser.load(in, 3), InputError);
  const std::string v2 = old_version_bytes(ps, 2);
  ParticleSystem denser_too = mixed(1400.0);
  io::BinaryReader in2(v2, "version 2");
  EXPECT_THROW(denser_too.load(in2, 2), InputError);
}

}  // namespace
}  // namespace bushel
