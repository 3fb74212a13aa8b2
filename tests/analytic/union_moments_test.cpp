// Union volume and moments against closed forms: a lone sphere, two overlapping spheres
// (sphere minus lens), and a seeded Monte Carlo estimate for an irregular clump.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "bushel/particles/union_moments.hpp"

namespace bushel {
namespace {

constexpr double pi = std::numbers::pi;

double sphere_volume(double r) { return 4.0 / 3.0 * pi * r * r * r; }

// Volume of the lens shared by spheres of radii r1, r2 whose centres are d apart.
double lens_volume(double r1, double r2, double d) {
  const double s = r1 + r2 - d;
  return pi * s * s * (d * d + 2 * d * (r1 + r2) - 3 * (r1 - r2) * (r1 - r2)) / (12 * d);
}

TEST(UnionMoments, SingleSphereVolumeCentroidInertia) {
  const std::vector<SphereElement> s = {{{0.3, -0.2, 0.1}, 1.0}};
  const UnionMoments m = integrate_union(s, 400);
  EXPECT_NEAR(m.volume / sphere_volume(1.0), 1.0, 2e-5);
  EXPECT_NEAR(m.centroid().x, 0.3, 1e-9);
  EXPECT_NEAR(m.centroid().y, -0.2, 1e-9);
  EXPECT_NEAR(m.centroid().z, 0.1, 1e-9);
  const Mat3 j = m.inertia_about_centroid();
  const double expected = 0.4 * sphere_volume(1.0);  // 2/5 m r^2 per unit density
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(j(i, i) / expected, 1.0, 5e-5);
    for (int k = 0; k < 3; ++k) {
      if (k != i) {
        EXPECT_NEAR(j(i, k) / expected, 0.0, 1e-9);
      }
    }
  }
}

TEST(UnionMoments, TwoOverlappingSpheresMatchLensFormula) {
  for (const double d : {0.3, 1.0, 1.7}) {
    const double r1 = 1.0, r2 = 0.8;
    const std::vector<SphereElement> s = {{{0, 0, 0}, r1}, {{d, 0, 0}, r2}};
    const double exact = sphere_volume(r1) + sphere_volume(r2) - lens_volume(r1, r2, d);
    EXPECT_NEAR(integrate_union(s, 400).volume / exact, 1.0, 5e-5) << "d = " << d;
  }
}

TEST(UnionMoments, ConvergesWithResolution) {
  // Oblique, off-axis clump so no symmetry of the grid helps.
  const std::vector<SphereElement> s = {
      {{0, 0, 0}, 1.0}, {{0.9, 0.4, -0.3}, 0.7}, {{-0.5, 0.8, 0.6}, 0.5}, {{0.2, -0.9, 0.7}, 0.6}};
  double previous_change = INFINITY;
  double previous = integrate_union(s, 50).volume;
  for (const int n : {100, 200, 400, 800}) {
    const double v = integrate_union(s, n).volume;
    const double change = std::abs(v - previous) / v;
    EXPECT_LT(change, previous_change) << "resolution " << n;
    previous_change = change;
    previous = v;
  }
  EXPECT_LT(previous_change, 1e-4);  // 400 -> 800 changes the volume by less than 0.01%
}

TEST(UnionMoments, AgreesWithMonteCarlo) {
  const std::vector<SphereElement> s = {{{0, 0, 0}, 1.0}, {{0.9, 0.4, -0.3}, 0.7}, {{-0.5, 0.8, 0.6}, 0.5}};
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.6, 2.0);
  const int n = 400000;
  int inside = 0;
  double sx = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    for (const auto& e : s) {
      if (norm2(p - e.centre) < e.radius * e.radius) {
        ++inside;
        sx += p.x;
        break;
      }
    }
  }
  const double box = std::pow(3.6, 3);
  const double mc_volume = box * inside / n;
  const UnionMoments m = integrate_union(s, 300);
  // Standard error of the hit fraction is about 0.3% here; allow 4 sigma.
  EXPECT_NEAR(m.volume / mc_volume, 1.0, 0.012);
  EXPECT_NEAR(m.centroid().x, sx / inside, 0.01);
}

TEST(UnionMoments, IndependentOfSphereOrderAndDeterministic) {
  std::vector<SphereElement> s = {{{0, 0, 0}, 1.0}, {{0.9, 0.4, -0.3}, 0.7}, {{-0.5, 0.8, 0.6}, 0.5}};
  const UnionMoments a = integrate_union(s, 200);
  const UnionMoments b = integrate_union(s, 200);
  EXPECT_EQ(a.volume, b.volume);  // bitwise: fixed summation order
  std::swap(s[0], s[2]);
  EXPECT_NEAR(integrate_union(s, 200).volume, a.volume, 1e-12 * a.volume);
}

TEST(UnionMoments, RejectsBadInput) {
  EXPECT_THROW(integrate_union({}, 100), std::invalid_argument);
  const std::vector<SphereElement> bad = {{{0, 0, 0}, -1.0}};
  EXPECT_THROW(integrate_union(bad, 100), std::invalid_argument);
  const std::vector<SphereElement> ok = {{{0, 0, 0}, 1.0}};
  EXPECT_THROW(integrate_union(ok, 2), std::invalid_argument);
}

}  // namespace
}  // namespace bushel
