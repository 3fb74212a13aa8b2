// Particle factories and sinks: the mass fractions over the run, the rate, no overlaps, and
// removal that keeps the remaining particles' contacts.
#include "bushel/insertion/factory.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "bushel/core/input_error.hpp"
#include "bushel/experiments/pour_scene.hpp"
#include "bushel/geometry/shapes.hpp"
#include "bushel/insertion/sink.hpp"
#include "bushel/particles/template_library.hpp"

namespace bushel {
namespace {

Simulation kanmark_simulation() {
  Simulation sim(wheat_settings(2e-6));
  for (const char* name : {"large_5s", "medium_5s", "small_5s"}) {
    sim.add_type({name, TemplateLibrary::builtin().get(name), materials::wheat()});
  }
  return sim;
}

FactorySpec kanmark_spec() {
  FactorySpec f;
  f.name = "pour";
  f.region = Region::cylinder({0, 0, 0.05}, 0.03, 0.08);
  f.types = {0, 1, 2};
  f.fractions = {0.815, 0.155, 0.030};
  f.total = 0.040;  // kg
  f.rate = 1.0;     // kg/s
  return f;
}

TEST(Factory, MeetsTheMassFractionsAndTheRateWithoutOverlaps) {
  Simulation sim = kanmark_simulation();
  Factory factory(kanmark_spec(), sim);
  // 1 ms at a time: the created mass follows the rate within one particle
  double largest = 0.0;
  for (const auto& t : sim.particles().types()) largest = std::max(largest, t.mass());
  for (int k = 1; k <= 10; ++k) {
    factory.run(sim, 1e-3);
    EXPECT_NEAR(factory.report().total_mass, 1.0 * k * 1e-3, largest) << k;
    // every type within one particle of its share at all times
    const auto f = factory.achieved_fractions();
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_LE(
          std::abs(f[i] * factory.report().total_mass - kanmark_spec().fractions[i] * factory.report().total_mass),
          largest);
    }
  }
  factory.run(sim, 1.0);
  EXPECT_TRUE(factory.done());
  EXPECT_NEAR(factory.report().total_mass, 0.040, largest);
  const auto f = factory.achieved_fractions();
  EXPECT_NEAR(f[0], 0.815, 0.01);
  EXPECT_NEAR(f[1], 0.155, 0.01);
  EXPECT_NEAR(f[2], 0.030, 0.01);
  // no two elements of different bodies overlap, and every element is inside the region
  const auto& ps = sim.particles();
  ASSERT_EQ(ps.bodies(), factory.report().total_count);
  sim.step(0);  // places the elements
  for (std::size_t i = 0; i < ps.spheres(); ++i) {
    EXPECT_TRUE(kanmark_spec().region.contains_sphere(ps.sphere_position[i], ps.radius[i] - 1e-12));
    for (std::size_t j = i + 1; j < ps.spheres(); ++j) {
      if (ps.owner[i] == ps.owner[j]) continue;
      EXPECT_GE(norm(ps.sphere_position[i] - ps.sphere_position[j]), ps.radius[i] + ps.radius[j]);
    }
  }
}

TEST(Factory, CountsByCountAndWaitsWhenTheRegionIsFull) {
  Simulation sim = kanmark_simulation();
  FactorySpec spec = kanmark_spec();
  spec.total_by_mass = false;
  spec.fractions_by_mass = false;
  spec.rate = 0.0;  // all at once
  spec.total = 100000;
  spec.region = Region::box({0, 0, 0.05}, {0.02, 0.02, 0.02});  // room for a few hundred
  spec.attempts = 50;
  Factory factory(spec, sim);
  factory.run(sim, 1e-3);
  EXPECT_FALSE(factory.done());
  EXPECT_GT(factory.report().total_count, 20u);
  EXPECT_GT(factory.report().waiting, 0u);
  const auto f = factory.achieved_fractions();
  const double n = static_cast<double>(factory.report().total_count);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_LE(std::abs(f[i] - spec.fractions[i]) * n, 1.0 + 1e-9);
}

TEST(Factory, CreatesOnTheFrontOfASurface) {
  // A 40 mm square sheet at z = 0.1 m facing up: every kernel is created touching it from
  // above (its centre one bounding radius over the sheet) and within its edges.
  Simulation sim = kanmark_simulation();
  FactorySpec spec = kanmark_spec();
  spec.surface = square_mesh(0.04, 4);
  for (Vec3& v : spec.surface.vertices) v.z += 0.1;
  spec.total = 0.0004;  // a dozen kernels: room on one sheet
  spec.rate = 0.0;
  Factory factory(spec, sim);
  factory.run(sim, 1e-3);
  EXPECT_TRUE(factory.done());
  const auto& ps = sim.particles();
  ASSERT_GT(ps.bodies(), 8u);
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    const double r = ps.types()[ps.body_type[b]].shape.bounding_radius();
    EXPECT_NEAR(ps.position[b].z, 0.1 + r, 1e-9);
    EXPECT_LE(std::abs(ps.position[b].x), 0.02);
    EXPECT_LE(std::abs(ps.position[b].y), 0.02);
  }
}

TEST(Factory, RejectsBadSpecs) {
  Simulation sim = kanmark_simulation();
  FactorySpec spec = kanmark_spec();
  spec.fractions = {0.5, 0.2, 0.2};
  EXPECT_THROW(Factory(spec, sim), InputError);
  spec = kanmark_spec();
  spec.region = Region::cylinder({0, 0, 0}, 0.002, 0.1);  // narrower than a kernel
  EXPECT_THROW(Factory(spec, sim), InputError);
  spec = kanmark_spec();
  spec.total = 0.0;
  EXPECT_THROW(Factory(spec, sim), InputError);
}

TEST(Sinks, RemoveAndCountByTypeWhileTheRestKeepsItsContactHistory) {
  // A settled bed of spheres; a sink takes the upper layer away. Every pair of the particles
  // left keeps its contact history (tangential and rolling springs) through the renumbering.
  PourSpec p;
  p.count = 300;
  PourScene scene = make_pour_scene(p);
  Simulation& sim = scene.simulation;
  sim.step(30000);
  auto histories = [&] {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<double>> h;
    auto& nl = const_cast<NeighborList&>(sim.neighbors());
    const auto& id = sim.particles().sphere_id;
    for (std::size_t k = 0; k < nl.pairs(); ++k) {
      const double* v = nl.history(k);
      if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0) continue;  // not in contact
      const auto a = id[nl.first(k)], b = id[nl.second(k)];
      h[{std::min(a, b), std::max(a, b)}] = std::vector<double>(v, v + nl.history_size());
    }
    return h;
  };
  const auto before = histories();
  double top = 0.0;
  for (const Vec3& x : sim.particles().position) top = std::max(top, x.z);
  std::vector<Sink> sinks = {{"top", Region::box({0, 0, top}, {0.2, 0.2, 0.006}), true, {}, {}}};
  Sink lost{"domain", {}, true, {}, {}};
  const Region domain = Region::box({0, 0, 0.1}, {0.2, 0.2, 0.3});
  std::size_t expected = 0;
  double expected_mass = 0.0;
  std::set<std::uint32_t> removed;
  for (std::size_t b = 0; b < sim.particles().bodies(); ++b) {
    if (!sinks[0].region.contains(sim.particles().position[b])) continue;
    ++expected, expected_mass += sim.particles().mass(b);
    removed.insert(sim.particles().sphere_id[sim.particles().first_sphere[b]]);
  }
  ASSERT_GT(expected, 5u);
  EXPECT_EQ(apply_sinks(sim, sinks, domain, lost), expected);
  EXPECT_EQ(sim.particles().bodies(), 300 - expected);
  EXPECT_EQ(sinks[0].count.at(0), expected);
  EXPECT_NEAR(sinks[0].mass.at(0), expected_mass, 1e-15);
  EXPECT_EQ(lost.count.at(0), 0u);
  EXPECT_EQ(sinks[0].total_count(), expected);
  EXPECT_NEAR(sinks[0].total_mass(), expected_mass, 1e-15);
  const auto after = histories();
  std::size_t kept = 0;
  for (const auto& [pair, h] : before) {
    if (removed.contains(pair.first) || removed.contains(pair.second)) continue;
    ASSERT_TRUE(after.contains(pair));
    EXPECT_EQ(after.at(pair), h);
    ++kept;
  }
  EXPECT_GT(kept, 100u);
  sim.step(100);
  EXPECT_EQ(sim.particles().bodies(), 300 - expected);
  // a particle thrown out of the domain is lost
  sim.particles().position[0] = {0, 0, 1.0};
  const double thrown = sim.particles().mass(0);
  apply_sinks(sim, sinks, domain, lost);
  EXPECT_EQ(lost.count.at(0), 1u);
  EXPECT_EQ(lost.total_count(), 1u);
  EXPECT_EQ(lost.total_mass(), thrown);
}

TEST(Sink, TotalsAddEveryType) {
  const Sink s{"under", {}, true, {2, 0, 3}, {0.125, 0.0, 0.25}};
  EXPECT_EQ(s.total_count(), 5u);
  EXPECT_EQ(s.total_mass(), 0.375);
  EXPECT_EQ((Sink{"none", {}, true, {}, {}}.total_count()), 0u);
  EXPECT_EQ((Sink{"none", {}, true, {}, {}}.total_mass()), 0.0);
}

}  // namespace
}  // namespace bushel
