// Margins per element (neighbor_stage.cpp, docs/engine.md): an element more than twice as fast
// as the 98th-percentile element gets a margin as many times half the skin (at most four
// times), so that a few fast grains do not make the whole list be rebuilt; the list stays a
// superset of the contacts, so the results are the same bits whatever the lists were.

#include <gtest/gtest.h>

#include <map>
#include <utility>
#include <vector>

#include "bushel/experiments/pour_scene.hpp"
#include "bushel/integrate/simulation.hpp"

namespace bushel {
namespace {

constexpr double dt = 1e-5;  // [s]

// n^3 resting spheres on a cubic lattice with gaps of `gap` [m], and one sphere at `shot`
// with velocity `v` [m/s]; a fixed skin [m], no gravity.
Simulation lattice_and_shot(int n, double gap, double skin, const Vec3& shot, const Vec3& v) {
  SimulationSettings s;
  s.gravity = {};
  s.dt = dt;
  s.skin = skin;
  Simulation sim(s);
  const auto t = sim.add_type(wheat_particle("sphere"));
  const double a = 2.0 * sim.particles().types()[t].shape.spheres[0].radius + gap;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) sim.add_body(t, {{a * i, a * j, a * k}, {}, {}, {}});
    }
  }
  sim.add_body(t, {shot, {}, v, {}});
  return sim;
}

TEST(ElementMargins, OneFastSphereAmongRestingOnesIsGivenFourTimesTheMargin) {
  // 1 m/s crosses half the skin (0.25 mm) in 25 steps, four times that in 100: 2,000 steps
  // take 20 builds (each due on the step after the sphere has passed its margin)
  const double skin = 0.5e-3;
  Simulation sim = lattice_and_shot(6, 1e-4, skin, {0.1, 0.0, 0.0}, {0.0, 1.0, 0.0});
  sim.step(1);
  const ParticleSystem& ps = sim.particles();
  for (std::size_t e = 0; e < ps.spheres(); ++e) {  // (sorted in space: found by its id)
    const bool fast = ps.body_id[ps.owner[e]] == ps.bodies() - 1;
    EXPECT_DOUBLE_EQ(sim.neighbors().margin(e), (fast ? 4 : 1) * 0.5 * skin);
  }
  const std::size_t builds = sim.neighbors().builds();
  sim.step(2000);
  const double per_build = 4 * 0.5 * skin / (1.0 * dt);
  EXPECT_NEAR(static_cast<double>(sim.neighbors().builds() - builds), 2000 / per_build, 1.0);
}

TEST(ElementMargins, AFastSphereHittingRestingOnesGivesTheSameBitsAtAnySkin) {
  // a sphere at 2 m/s into a lattice, on a line through its spheres: contacts found late
  // (or missed) would change the state
  std::map<std::uint32_t, std::pair<Vec3, Vec3>> state[2];  // by stable id: position, velocity
  const double skins[2] = {0.2e-3, 0.6e-3};
  for (int k = 0; k < 2; ++k) {
    Simulation sim = lattice_and_shot(5, 2e-5, skins[k], {-0.01, 0.0, 0.0}, {2.0, 0.0, 0.0});
    sim.step(3000);
    const ParticleSystem& ps = sim.particles();
    for (std::size_t b = 0; b < ps.bodies(); ++b) state[k][ps.body_id[b]] = {ps.position[b], ps.velocity[b]};
    EXPECT_LT(state[k].at(125).second.x, 1.0);  // the collision happened
  }
  for (const auto& [id, s0] : state[0]) {
    const auto& s1 = state[1].at(id);
    for (const auto& [a, b] : {std::pair{s0.first, s1.first}, std::pair{s0.second, s1.second}}) {
      ASSERT_EQ(a.x, b.x) << id;
      ASSERT_EQ(a.y, b.y) << id;
      ASSERT_EQ(a.z, b.z) << id;
    }
  }
}

}  // namespace
}  // namespace bushel
