// The critical time step of a contact (critical_step.hpp, docs/physics.md section 3): the
// modes of lone spheres by hand, the clump's rotational inverse masses against a search over
// directions, and the engine itself, which must oscillate stably just below the normal
// mode's limit and blow up just above it.
#include "bushel/integrate/critical_step.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "bushel/contact/time_scales.hpp"
#include "bushel/experiments/pour_scene.hpp"
#include "bushel/integrate/simulation.hpp"

namespace bushel {
namespace {

PairCoefficients wheat_on(const Material& other, double restitution) {
  return make_pair_coefficients(materials::wheat(), other, {restitution, 0.27, 0.0});
}

TEST(CriticalStep, LoneSpheresByHand) {
  const ParticleType sphere = wheat_particle("sphere");
  const ContactSide s = contact_sides(sphere).at(0);
  const double m = sphere.mass(), r = 1.82e-3;
  EXPECT_NEAR(s.radius, r, 1e-12);
  EXPECT_NEAR(s.normal_turning, 0.0, 1e-12 / m);     // the normal passes through the centre
  EXPECT_NEAR(s.tangential_turning * m, 2.5, 1e-9);  // r^2 / (2/5 m r^2)
  for (const double e : {1.0, 0.5}) {
    const PairCoefficients c = wheat_on(materials::wheat(), e);
    const ContactModes modes = contact_modes(s, s, c);
    const double s_n = 2.0 * c.youngs_modulus * std::sqrt(0.5 * r * 0.05 * r);
    const double omega_n = std::sqrt(s_n * 2.0 / m), omega_t = std::sqrt(c.stiffness_ratio * s_n * 7.0 / m);
    EXPECT_NEAR(modes.normal.omega / omega_n, 1.0, 1e-12);
    EXPECT_NEAR(modes.tangential.omega / omega_t, 1.0, 1e-12);
    // damping ratio gamma/2 sqrt(m*/m_mode): m* = m/2; normal m/2, tangential m/7
    const double zeta_n = 0.5 * c.damping, zeta_t = 0.5 * c.damping * std::sqrt(3.5);
    EXPECT_NEAR(modes.normal.zeta, zeta_n, 1e-12);
    EXPECT_NEAR(modes.tangential.zeta, zeta_t, 1e-12);
    EXPECT_NEAR(modes.tangential.dt * omega_t, 2.0 * (std::sqrt(1 + zeta_t * zeta_t) - zeta_t), 1e-12);
    // the tangential mode, lighter and nearly as stiff, sets the step
    const CriticalStep step = critical_step(s, s, c);
    EXPECT_TRUE(step.tangential);
    EXPECT_EQ(step.dt, modes.tangential.dt);
  }
  EXPECT_EQ(contact_modes(s, s, wheat_on(materials::wheat(), 1.0)).normal.zeta, 0.0);
  // against a wall: R* = r and m* = m
  const PairCoefficients steel = wheat_on(materials::steel(), 1.0);
  const ContactModes wall = contact_modes(s, ContactSide{}, steel);
  EXPECT_NEAR(wall.normal.omega, std::sqrt(2.0 * steel.youngs_modulus * std::sqrt(r * 0.05 * r) / m), 1e-9);
}

TEST(CriticalStep, ClumpTurningAgainstASearchOverDirections) {
  // For each element of the 5-sphere kernel: max over n of (d x n)^T I^-1 (d x n) must equal
  // normal_turning, and (c x t)^T I^-1 (c x t), c = d + r n, t across n, must stay under
  // tangential_turning and come near it.
  const ParticleType clump = wheat_particle("large_5s");
  const Vec3 moments = clump.shape.principal_inertia(clump.material.density);
  auto quadratic = [&](const Vec3& u) { return u.x * u.x / moments.x + u.y * u.y / moments.y + u.z * u.z / moments.z; };
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss;
  auto direction = [&] {
    const Vec3 v{gauss(rng), gauss(rng), gauss(rng)};
    return v / norm(v);
  };
  const std::vector<ContactSide> sides = contact_sides(clump);
  ASSERT_EQ(sides.size(), clump.shape.spheres.size());
  for (std::size_t k = 0; k < sides.size(); ++k) {
    const Vec3 d = clump.shape.spheres[k].centre;
    const double r = clump.shape.spheres[k].radius;
    double normal = 0.0, across = 0.0;
    for (int s = 0; s < 100'000; ++s) {
      const Vec3 n = direction();
      normal = std::max(normal, quadratic(cross(d, n)));
      const Vec3 t = normalized(cross(n, direction()));
      across = std::max(across, quadratic(cross(d + r * n, t)));
    }
    EXPECT_LE(normal, sides[k].normal_turning * (1 + 1e-12));
    EXPECT_GE(normal, 0.999 * sides[k].normal_turning) << "element " << k;
    EXPECT_EQ(sides[k].normal_turning == 0.0, norm(d) < 1e-12) << "element " << k;  // only the centre's is 0
    // the search finds the largest value: no sampled direction above it, and some close
    EXPECT_LE(across, sides[k].tangential_turning * (1 + 1e-9));
    EXPECT_GT(across, 0.999 * sides[k].tangential_turning) << "element " << k;
    // under the triangle-inequality bound, which is loose off the centre
    const double bound = std::pow(std::sqrt(sides[k].normal_turning) + r / std::sqrt(moments.x), 2);
    EXPECT_LE(sides[k].tangential_turning, bound * (1 + 1e-12));
  }
}

// A wheat sphere resting on a steel plane under a gravity that presses it 5 % of its radius
// in, nudged by 1 % of that overlap: the deepest departure from rest over 3000 steps [share of
// the overlap at rest].
double departure(double dt_over_critical) {
  const ParticleType sphere = wheat_particle("sphere");
  const double r = sphere.shape.spheres[0].radius, m = sphere.mass();
  const PairCoefficients c = wheat_on(materials::steel(), 1.0);
  const double rest = 0.05 * r;
  const double g = 4.0 / 3.0 * c.youngs_modulus * std::sqrt(r) * std::pow(rest, 1.5) / m;
  const double dt = dt_over_critical * contact_modes(contact_sides(sphere)[0], ContactSide{}, c).normal.dt;
  SimulationSettings settings;
  settings.dt = dt;
  settings.gravity = {0.0, 0.0, -g};
  settings.contacts = ContactTable({1.0, 0.27, 0.0});
  Simulation sim(settings);
  const auto t = sim.add_type(sphere);
  sim.add_part(plane_part("floor", materials::steel(), {0, 0, 0}, {0, 0, 1}));
  sim.add_body(t, {{0, 0, r - 1.01 * rest}, {}, {}, {}});
  double worst = 0.0;
  for (int k = 0; k < 3000; ++k) {
    sim.step();
    const double overlap = r - sim.particles().position[0].z;
    worst = std::max(worst, std::abs(overlap - rest) / rest);
    if (!std::isfinite(overlap) || worst > 1e3) break;
  }
  return worst;
}

TEST(CriticalStep, TheEngineOscillatesBelowTheNormalLimitAndBlowsUpAbove) {
  // Symplectic Euler on a spring is stable for omega dt < 2: at 0.97 of the limit the nudge
  // stays a nudge (amplified at most 1/sqrt(1 - (omega dt / 2)^2) = 4.1 times), at 1.03 it
  // grows by 1.6 a step.
  EXPECT_LT(departure(0.97), 0.1);
  EXPECT_GT(departure(1.03), 1.0);
  EXPECT_LT(departure(0.5), 0.02);
}

TEST(CriticalStep, TheWheatScenes) {
  // Wheat spheres and the 5-sphere kernel in a steel container (the pour scene's table): the
  // step is set by a tangential mode, and the clump's, whose elements carry the whole kernel,
  // is a larger share of its smallest element's Rayleigh step than the sphere's.
  const ContactTable table = wheat_settings(1e-6).contacts;
  const std::vector<Part> steel{plane_part("floor", materials::steel(), {0, 0, 0}, {0, 0, 1})};
  const ParticleType sphere = wheat_particle("sphere"), clump = wheat_particle("large_5s");
  const CriticalStep s = critical_time_step({sphere}, steel, table);
  const CriticalStep k = critical_time_step({clump}, steel, table);
  EXPECT_TRUE(s.tangential);
  EXPECT_EQ(s.pair.substr(0, 6), "sphere");
  const double s_ratio = s.dt / rayleigh_step(sphere), k_ratio = k.dt / rayleigh_step(clump);
  EXPECT_GT(s_ratio, 0.3);
  EXPECT_LT(s_ratio, 1.0);
  EXPECT_GT(k_ratio, 1.2 * s_ratio) << s_ratio << " " << k_ratio;
  // a mixture is bounded by its stiffest, lightest contact
  EXPECT_LE(critical_time_step({sphere, clump}, steel, table).dt, std::min(s.dt, k.dt));
  std::printf("critical step / Rayleigh step: sphere %.3f (%s), large_5s %.3f (%s, %s)\n", s_ratio, s.pair.c_str(),
              k_ratio, k.pair.c_str(), k.tangential ? "tangential" : "normal");
}

}  // namespace
}  // namespace bushel
