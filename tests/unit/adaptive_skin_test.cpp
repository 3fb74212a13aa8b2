// The adaptive Verlet skin (neighbor_stage.cpp, docs/engine.md): at each build that motion
// makes due it takes the skin that minimises the modelled cost of a step,
//   s = s0 sqrt((c_e N + c_p T) / (interval E)),   c_e = 72, c_p = 6 pair tests,
// within 0.11 to 0.35 of the largest element diameter and at most twice or half the last; a
// wide skin with no build for 160, 320, 640, ... steps is narrowed when that pays; a skin set
// in the settings is kept.
//
// The lattice below moves as one at speed v, so nothing touches (T = 0), the list keeps its
// E pairs at every skin in the range, and a build comes every s / (2 v dt) steps: the model's
// fixed point is s = 2 v dt c_e N / E, which these tests check against.

#include <gtest/gtest.h>

#include <cmath>

#include "bushel/experiments/pour_scene.hpp"
#include "bushel/integrate/simulation.hpp"

namespace bushel {
namespace {

constexpr double build_cost_per_element = 72.0;  // c_e [pair tests]
constexpr double dt = 1e-5;                      // [s]

SimulationSettings settings(double skin) {
  SimulationSettings s;
  s.gravity = {};
  s.dt = dt;
  s.skin = skin;
  return s;
}

// n^3 spheres on a cubic lattice whose gap is a tenth of the narrowest skin: each has its
// lattice neighbours (and only those) in the list at any skin of the range.
struct Lattice {
  explicit Lattice(int n, double skin = 0.0) : sim(settings(skin)) {
    const auto t = sim.add_type(wheat_particle("sphere"));
    const double r = sim.particles().types()[t].shape.spheres[0].radius;
    least = 0.22 * r, most = 0.70 * r;
    const double a = 2.0 * r + 0.1 * least;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        for (int k = 0; k < n; ++k) sim.add_body(t, {{a * i, a * j, a * k}, {}, {}, {}});
      }
    }
    pairs = 3.0 * n * n * (n - 1);
    elements = static_cast<double>(n) * n * n;
  }
  // All moving along x at `speed` [m/s] for `steps` steps.
  void move(double speed, std::uint64_t steps) {
    for (auto& v : sim.particles().velocity) v = {speed, 0.0, 0.0};
    sim.step(steps);
  }
  // The skin [m] the model settles on at `speed`.
  double fixed_point(double speed) const { return 2.0 * speed * dt * build_cost_per_element * elements / pairs; }
  double skin() const { return sim.neighbors().skin(); }

  Simulation sim;
  double least = 0.0, most = 0.0, pairs = 0.0, elements = 0.0;
};

TEST(AdaptiveSkin, SettlesWhereTheListCostsAsMuchAsItsBuilds) {
  Lattice l(4);
  l.move(0.0, 1);
  EXPECT_DOUBLE_EQ(l.skin(), l.least);
  ASSERT_EQ(l.sim.neighbors().pairs(), static_cast<std::size_t>(l.pairs));
  // a speed whose fixed point is 1.4 times the narrowest skin: it gets there within a few
  // builds (the interval is a whole number of steps, hence the 5 %)
  const double speed = 1.4 * l.least / l.fixed_point(1.0);
  l.move(speed, 3000);
  EXPECT_NEAR(l.skin() / l.fixed_point(speed), 1.0, 0.05);
  EXPECT_EQ(l.sim.neighbors().pairs(), static_cast<std::size_t>(l.pairs));
  // twice as fast: twice as wide, still in range
  const double faster = 2.0 * speed;
  ASSERT_LT(l.fixed_point(faster), l.most);
  l.move(faster, 3000);
  EXPECT_NEAR(l.skin() / l.fixed_point(faster), 1.0, 0.05);
  // ten times faster than that: the widest, and no wider
  l.move(10.0 * faster, 2000);
  EXPECT_DOUBLE_EQ(l.skin(), l.most);
  // slow (a fixed point under the narrowest): the narrowest
  l.move(0.2 * speed, 20000);
  EXPECT_DOUBLE_EQ(l.skin(), l.least);
}

TEST(AdaptiveSkin, AWideSkinAtRestNarrowsAfter160StepsAndThenStays) {
  Lattice l(4);
  l.move(30.0 * l.least / l.fixed_point(1.0), 2000);
  ASSERT_DOUBLE_EQ(l.skin(), l.most);
  // at rest no build is due; at 160 steps since the last the model says the narrowest (it
  // would take 160 steps per build to pay for a skin of 0.56 of the widest)
  const std::size_t builds = l.sim.neighbors().builds();
  l.move(0.0, 2000);
  EXPECT_DOUBLE_EQ(l.skin(), l.least);
  EXPECT_LE(l.sim.neighbors().builds() - builds, 2u);
  l.move(0.0, 5000);
  EXPECT_LE(l.sim.neighbors().builds() - builds, 2u);
}

TEST(AdaptiveSkin, WithNoPairsToTestTheSkinGrowsToTheWidest) {
  // two spheres far apart: a wider skin costs nothing, and fewer builds save their cost
  Simulation sim(settings(0.0));
  const auto t = sim.add_type(wheat_particle("sphere"));
  sim.add_body(t, {{-0.05, 0, 0}, {}, {0, -1.0, 0}, {}});
  sim.add_body(t, {{0.05, 0, 0}, {}, {0, 1.0, 0}, {}});
  sim.step(2000);
  EXPECT_DOUBLE_EQ(sim.neighbors().skin(), 0.70 * sim.particles().radius[0]);
}

TEST(AdaptiveSkin, ASkinSetInTheSettingsIsKept) {
  Lattice l(3, 0.5e-3);
  l.move(5.0, 1000);
  EXPECT_GT(l.sim.neighbors().builds(), 100u);
  EXPECT_DOUBLE_EQ(l.skin(), 0.5e-3);
}

}  // namespace
}  // namespace bushel
