// Regions: membership, sampling, and the exact part of a sphere inside, against closed forms
// (caps, halves, octants) and brute-force counting on a grid.
#include "bushel/geometry/region.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace bushel {
namespace {

constexpr double pi = std::numbers::pi;
double ball(double r) { return 4.0 / 3.0 * pi * r * r * r; }
// A spherical cap of height h of a sphere of radius r.
double cap(double r, double h) { return pi * h * h * (3.0 * r - h) / 3.0; }

// The volume inside by counting the points of a fine grid over the sphere's cube.
double counted(const Region& g, const Vec3& c, double r, int n = 200) {
  const double step = 2.0 * r / n;
  long hits = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const Vec3 p = c + Vec3{-r + (i + 0.5) * step, -r + (j + 0.5) * step, -r + (k + 0.5) * step};
        if (norm2(p - c) <= r * r && g.contains(p)) ++hits;
      }
    }
  }
  return static_cast<double>(hits) * step * step * step;
}

TEST(Region, CylinderAndBoxMembershipAndVolume) {
  const Region cyl = Region::cylinder({0, 0, 1}, 2.0, 3.0);
  EXPECT_TRUE(cyl.contains({1.9, 0, 1.1}));
  EXPECT_FALSE(cyl.contains({1.5, 1.5, 2.0}));  // outside the circle
  EXPECT_FALSE(cyl.contains({0, 0, 0.9}));      // below the base
  EXPECT_NEAR(cyl.volume(), pi * 4.0 * 3.0, 1e-12);
  const Region box = Region::box({1, 2, 3}, {2, 4, 6});
  EXPECT_TRUE(box.contains({1.9, 3.9, 5.9}));
  EXPECT_FALSE(box.contains({2.1, 2, 3}));
  EXPECT_NEAR(box.volume(), 48.0, 1e-12);
}

TEST(Region, SamplesStayInsideTheShrunkRegion) {
  std::mt19937_64 rng(3);
  for (const Region& g : {Region::cylinder({0, 0, 0}, 0.05, 0.1), Region::box({0, 0, 0.5}, {0.1, 0.2, 0.3})}) {
    for (int k = 0; k < 2000; ++k) EXPECT_TRUE(g.contains_sphere(g.sample(rng, 0.004), 0.004 - 1e-12));
  }
}

TEST(Region, SphereVolumeInsideMatchesClosedForms) {
  const double r = 1.8e-3;
  const Region box = Region::box({0, 0, 0}, {0.02, 0.02, 0.02});
  EXPECT_NEAR(box.sphere_volume_inside({0, 0, 0}, r), ball(r), 1e-9 * ball(r));
  EXPECT_NEAR(box.sphere_volume_inside({0.01, 0, 0}, r), 0.5 * ball(r), 1e-6 * ball(r));      // halved by a face
  EXPECT_NEAR(box.sphere_volume_inside({0.01, 0.01, 0.01}, r), ball(r) / 8, 1e-6 * ball(r));  // a corner
  EXPECT_NEAR(box.sphere_volume_inside({0.01 + 0.6 * r, 0, 0}, r), cap(r, 0.4 * r), 1e-6 * ball(r));
  EXPECT_EQ(box.sphere_volume_inside({0.01 + r, 0, 0}, r), 0.0);
  // a cylinder's top and base cut caps
  const Region cyl = Region::cylinder({0, 0, 0}, 0.01, 0.01);
  EXPECT_NEAR(cyl.sphere_volume_inside({0, 0, 0.01 - 0.3 * r}, r), ball(r) - cap(r, 0.7 * r), 1e-6 * ball(r));
  EXPECT_NEAR(cyl.sphere_volume_inside({0.002, 0.001, -0.5 * r}, r), cap(r, 0.5 * r), 1e-6 * ball(r));
}

TEST(Region, SphereVolumeInsideMatchesCountingWhereNoClosedFormExists) {
  const double r = 1.0;
  // cut by a cylinder's curved wall (and its base), and by a box's edge
  const Region cyl = Region::cylinder({0, 0, 0}, 3.0, 10.0);
  for (const Vec3& c : {Vec3{2.6, 0.4, 5.0}, Vec3{2.2, 1.5, 0.4}}) {
    EXPECT_NEAR(cyl.sphere_volume_inside(c, r), counted(cyl, c, r), 2e-3 * ball(r)) << c.x << " " << c.y;
  }
  const Region box = Region::box({0, 0, 0}, {4, 4, 4});
  const Vec3 c{1.7, -1.5, 0.3};
  EXPECT_NEAR(box.sphere_volume_inside(c, r), counted(box, c, r), 2e-3 * ball(r));
}

}  // namespace
}  // namespace bushel
