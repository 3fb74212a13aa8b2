// clearance(): the broad phase drops a sphere-wall pair while the sphere is further than the
// skin from the wall, so clearance must never overstate the distance to a touch.
#include <gtest/gtest.h>

#include <random>

#include "bushel/geometry/wall.hpp"

using namespace bushel;

namespace {

template <class Shape>
void expect_safe_lower_bound(const Shape& shape, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coord(-0.06, 0.06), rad(0.5e-3, 4e-3);
  std::normal_distribution<double> n01;
  int near = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p{coord(rng), coord(rng), coord(rng)};
    const double r = rad(rng);
    const double c = clearance(shape, p, r);
    if (touch(shape, p, r).touching) {
      EXPECT_LE(c, 0.0) << "touching with positive clearance at " << p.x << " " << p.y << " " << p.z;
      continue;
    }
    if (c <= 0.0 || c > 0.01) continue;
    ++near;
    for (int m = 0; m < 8; ++m) {  // any move shorter than the clearance keeps it apart
      const Vec3 u = 0.999 * c * normalized(Vec3{n01(rng), n01(rng), n01(rng)});
      EXPECT_FALSE(touch(shape, p + u, r).touching);
    }
  }
  EXPECT_GT(near, 1000);
}

}  // namespace

TEST(Wall, PlaneClearanceIsTheGap) {
  const PlaneShape floor{{0, 0, -0.01}, {0, 0, 1}};
  EXPECT_DOUBLE_EQ(clearance(floor, {0.3, -0.2, 0.0}, 2e-3), 0.008);
  EXPECT_TRUE(touch(floor, {0.3, -0.2, 0.0 - 0.008 - 1e-9}, 2e-3).touching);
  expect_safe_lower_bound(floor, 1);
  expect_safe_lower_bound(PlaneShape{{0.01, 0, 0}, normalized(Vec3{-1, 2, 0.5})}, 2);
}

TEST(Wall, CylinderClearanceIsALowerBound) {
  const CylinderShape side{{0.002, -0.001, 0}, 0.045, -0.02, 0.03};
  // Inside the band: the radial gap.
  EXPECT_NEAR(clearance(side, {0.002, -0.001, 0.0}, 2e-3), 0.043, 1e-15);
  // Above the band: the centre must come down to z_max first.
  EXPECT_NEAR(clearance(side, {0.002 + 0.044, -0.001, 0.035}, 2e-3), 0.005, 1e-15);
  expect_safe_lower_bound(side, 3);
}
