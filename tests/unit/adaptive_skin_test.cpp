// The adaptive Verlet skin (Simulation::rebuild): it widens while the fastest element crosses
// half of it in fewer than 40 steps, narrows while that takes more than 160 (and every 160
// steps without a build), stays between 0.11 and 0.35 of the largest element diameter, and a
// skin set in the settings is kept.

#include <gtest/gtest.h>

#include "bushel/experiments/pour_scene.hpp"
#include "bushel/integrate/simulation.hpp"

namespace bushel {
namespace {

// Two spheres far apart in free space, moving apart at `speed` [m/s] along y.
struct Pair {
  explicit Pair(double skin = 0.0) : sim(settings(skin)) {
    auto& ps = sim.particles();
    const auto t = sim.add_type(wheat_particle("sphere"));
    sim.add_body(t, {{-0.05, 0, 0}, {}, {}, {}});
    sim.add_body(t, {{0.05, 0, 0}, {}, {}, {}});
    radius = ps.radius[0];
  }
  static SimulationSettings settings(double skin) {
    SimulationSettings s;
    s.gravity = {};
    s.dt = 1e-5;
    s.skin = skin;
    return s;
  }
  void move(double speed, std::uint64_t steps) {
    auto& ps = sim.particles();
    ps.velocity[0] = {0, -speed, 0};
    ps.velocity[1] = {0, speed, 0};
    sim.step(steps);
  }
  Simulation sim;
  double radius = 0.0;  // [m]
};

TEST(AdaptiveSkin, WidensForFastElementsAndNarrowsForSlowOnes) {
  Pair p;
  p.move(0.0, 1);
  const double least = 0.22 * p.radius, most = 0.70 * p.radius;
  EXPECT_DOUBLE_EQ(p.sim.neighbors().skin(), least);
  // 100 steps to cross half the narrowest skin: within 40 to 160, so it stays
  p.move(0.5 * least / (100 * 1e-5), 2000);
  EXPECT_GE(p.sim.neighbors().builds(), 15u);
  EXPECT_DOUBLE_EQ(p.sim.neighbors().skin(), least);
  // 10 steps: it widens by 1.25 a build, up to 0.35 d, and stays there
  const std::size_t builds = p.sim.neighbors().builds();
  p.move(0.5 * least / (10 * 1e-5), 1000);
  EXPECT_DOUBLE_EQ(p.sim.neighbors().skin(), most);
  // (6 builds to get there, then one every 32 steps instead of every 10)
  EXPECT_LT(p.sim.neighbors().builds() - builds, 45u);
  // 1,000 steps across half the narrowest: it narrows again, down to 0.11 d
  p.move(0.5 * least / (1000 * 1e-5), 1000);
  EXPECT_LT(p.sim.neighbors().skin(), most);
  p.move(0.5 * least / (1000 * 1e-5), 1000);
  EXPECT_DOUBLE_EQ(p.sim.neighbors().skin(), least);
  // and at rest too: one build every 161 steps while it is wider than the least
  p.move(0.5 * least / (10 * 1e-5), 200);
  EXPECT_DOUBLE_EQ(p.sim.neighbors().skin(), most);
  const std::size_t before_rest = p.sim.neighbors().builds();
  p.move(0.0, 6 * 161);
  EXPECT_DOUBLE_EQ(p.sim.neighbors().skin(), least);
  EXPECT_EQ(p.sim.neighbors().builds() - before_rest, 6u);
  p.move(0.0, 1000);
  EXPECT_EQ(p.sim.neighbors().builds() - before_rest, 6u);
}

TEST(AdaptiveSkin, ASkinSetInTheSettingsIsKept) {
  Pair p(0.5e-3);
  p.move(5.0, 1000);
  EXPECT_GT(p.sim.neighbors().builds(), 100u);
  EXPECT_DOUBLE_EQ(p.sim.neighbors().skin(), 0.5e-3);
}

}  // namespace
}  // namespace bushel
