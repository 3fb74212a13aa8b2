// A body's force and torque of the last step (Simulation::body_force), which the engine keeps
// in its first element's contact sums instead of per-body arrays: gravity alone on a free
// body, equal and opposite contact forces on two touching spheres, each body's own when other
// bodies are removed and the rest renumbered and sorted, zero for a body added since the step.

#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "bushel/experiments/pour_scene.hpp"
#include "bushel/integrate/simulation.hpp"

namespace bushel {
namespace {

BodyState at(const Vec3& x) { return {.position = x, .orientation = {}, .velocity = {}, .angular_velocity = {}}; }

std::map<std::uint32_t, Vec3> forces_by_id(const Simulation& sim) {
  std::map<std::uint32_t, Vec3> f;
  for (std::size_t b = 0; b < sim.particles().bodies(); ++b) f[sim.particles().body_id[b]] = sim.body_force(b);
  return f;
}

TEST(BodyForces, FollowTheirBodiesAndAddUp) {
  const ParticleType sphere = wheat_particle("sphere"), clump = wheat_particle("large_5s");
  SimulationSettings settings;
  settings.dt = 0.2 * rayleigh_step(sphere);
  settings.sort_every = 1;  // (every build sorts: remove_bodies renumbers twice)
  Simulation sim(settings);
  const auto ts = sim.add_type(sphere), tc = sim.add_type(clump);
  const double r = sphere.shape.spheres[0].radius;
  // Added top to bottom, so that the spatial sort (z-major) reverses them.
  const std::size_t free_sphere = 0, a = 2, b = 3;
  sim.add_body(ts, at({0.0, 0.0, 0.05}));
  sim.add_body(tc, at({0.02, 0.0, 0.03}));
  sim.add_body(ts, at({0.0, 0.0, 0.01}));
  sim.add_body(ts, at({0.0, 0.0, 0.01 - 1.99 * r}));  // overlapping a by 0.01 r
  EXPECT_EQ(norm(sim.body_force(a)), 0.0);            // (no step yet)
  sim.step(1);

  const ParticleSystem& ps = sim.particles();
  std::size_t free_now = 0, a_now = 0, b_now = 0;
  for (std::size_t k = 0; k < ps.bodies(); ++k) {
    if (ps.body_id[k] == free_sphere) free_now = k;
    if (ps.body_id[k] == a) a_now = k;
    if (ps.body_id[k] == b) b_now = k;
  }
  const Vec3 weight = ps.mass(free_now) * settings.gravity;
  EXPECT_EQ(sim.body_force(free_now), weight);  // gravity plus zero sums: exactly
  EXPECT_EQ(sim.body_torque(free_now), Vec3{});
  const Vec3 contact = sim.body_force(a_now) - weight;
  EXPECT_GT(contact.z, 1e-3) << "the lower sphere pushes the upper one up";
  EXPECT_NEAR(norm(sim.body_force(a_now) + sim.body_force(b_now) - 2.0 * weight), 0.0, 1e-12 * norm(contact));

  // A body added below the others, then the lowest of the old ones removed: the removal
  // renumbers the rest, and the sort that follows moves the new body to the front.
  const std::map<std::uint32_t, Vec3> before = forces_by_id(sim);
  const std::uint32_t added = sim.add_body(ts, at({0.0, 0.0, -0.05}));
  EXPECT_EQ(sim.body_force(ps.bodies() - 1), Vec3{});
  const std::vector<std::size_t> gone{b_now};
  sim.remove_bodies(gone);
  ASSERT_EQ(ps.bodies(), 4u);
  ASSERT_EQ(ps.body_id[0], added);
  for (std::size_t k = 0; k < ps.bodies(); ++k) {
    EXPECT_EQ(sim.body_force(k), ps.body_id[k] == added ? Vec3{} : before.at(ps.body_id[k])) << k;
  }
}

}  // namespace
}  // namespace bushel
