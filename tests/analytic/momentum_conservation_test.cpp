// Pair forces are equal and opposite and act at one contact point, so in free space a bed
// keeps its total momentum and its total angular momentum about any point (symplectic Euler
// keeps both exactly: each step adds dt times the sum of x_b x F + tau over the bodies, zero
// pair by pair when every arm ends at the contact point). A mixed bed of lone spheres and
// 5-sphere clumps with two sets of contact parameters puts lone pairs, clump pairs and mixed
// pairs into the same batches, so this also checks that the batches' shortcuts (offsets and
// coefficients not stored while all lanes share them) hand every contact its own arms.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "bushel/experiments/pour_scene.hpp"
#include "bushel/integrate/simulation.hpp"

namespace bushel {
namespace {

struct Totals {
  Vec3 momentum, angular_momentum;  // [kg m/s], [kg m2/s] about the origin
  double momentum_scale = 0.0, angular_scale = 0.0;
};

Totals totals(const ParticleSystem& p) {
  Totals t;
  for (std::size_t b = 0; b < p.bodies(); ++b) {
    const Vec3 m_v = p.mass(b) * p.velocity[b];
    t.momentum += m_v;
    t.angular_momentum += cross(p.position[b], m_v) + p.angular_momentum_of(b);
    t.momentum_scale += norm(m_v);
    t.angular_scale += norm(p.position[b]) * norm(m_v) + norm(p.angular_momentum_of(b));
  }
  return t;
}

class MixedBed : public testing::TestWithParam<std::string> {};

TEST_P(MixedBed, KeepsMomentumAndAngularMomentum) {
  const ParticleType sphere = wheat_particle("sphere"), clump = wheat_particle("large_5s");
  ASSERT_NE(sphere.name, clump.name);
  SimulationSettings settings;
  settings.gravity = {};
  settings.rolling = GetParam();
  settings.dt = 0.2 * std::min(rayleigh_step(sphere), rayleigh_step(clump));
  settings.contacts = ContactTable({0.5, 0.3, 0.01});
  settings.contacts.set(sphere.name, clump.name, {0.4, 0.5, 0.02});
  Simulation sim(settings);
  auto& ps = sim.particles();
  const auto ts = sim.add_type(sphere), tc = sim.add_type(clump);
  const std::vector<Vec3> cloud = random_cloud(1200, 0.045, 6.3e-3, 0.35, 11);
  Vec3 centre;
  for (const Vec3& x : cloud) centre += x / static_cast<double>(cloud.size());
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01;
  for (std::size_t k = 0; k < cloud.size(); ++k) {
    const Quat q = normalized(Quat{n01(rng), n01(rng), n01(rng), n01(rng)});
    // Falling in towards the centre (and tumbling), so that the bed is soon dense.
    const Vec3 v = -150.0 * (cloud[k] - centre) + 0.1 * Vec3{n01(rng), n01(rng), n01(rng)};
    sim.add_body(k % 2 == 0 ? ts : tc, {cloud[k], q, v, 30.0 * Vec3{n01(rng), n01(rng), n01(rng)}});
  }
  sim.step(1);  // every body's angular momentum set by the integrator
  const Totals before = totals(ps);
  std::size_t contacts = 0;
  for (int k = 0; k < 60; ++k) {
    sim.step(25);
    contacts += sim.contacts();
  }
  EXPECT_GT(contacts, 60u * 200u) << contacts;  // the bed really collides
  const Totals after = totals(ps);
  // Rounding only: 1e-12 of the sums of magnitudes (a wrong arm shows at 1e-7 and above).
  EXPECT_LT(norm(after.momentum - before.momentum), 1e-12 * before.momentum_scale);
  EXPECT_LT(norm(after.angular_momentum - before.angular_momentum), 1e-12 * before.angular_scale);
}

INSTANTIATE_TEST_SUITE_P(RollingModels, MixedBed, testing::Values("none", "epsd", "liggghts_cdt"));

}  // namespace
}  // namespace bushel
