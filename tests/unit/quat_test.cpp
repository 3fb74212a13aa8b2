#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "bushel/core/quat.hpp"

namespace bushel {
namespace {

void expect_near(const Vec3& a, const Vec3& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Quat, QuarterTurnAboutZ) {
  const Quat q = Quat::from_axis_angle({0, 0, 1}, std::numbers::pi / 2);
  expect_near(rotate(q, {1, 0, 0}), {0, 1, 0}, 1e-15);
  expect_near(rotate_inverse(q, {0, 1, 0}), {1, 0, 0}, 1e-15);
}

TEST(Quat, MatrixRoundTripAndComposition) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n;
  for (int i = 0; i < 200; ++i) {
    const Quat a = normalized(Quat{n(rng), n(rng), n(rng), n(rng)});
    const Quat b = normalized(Quat{n(rng), n(rng), n(rng), n(rng)});
    const Vec3 v{n(rng), n(rng), n(rng)};
    expect_near(rotate(a * b, v), rotate(a, rotate(b, v)), 1e-12);
    expect_near(to_matrix(a) * v, rotate(a, v), 1e-12);
    const Quat back = Quat::from_matrix(to_matrix(a));
    expect_near(rotate(back, v), rotate(a, v), 1e-12);
    EXPECT_GE(back.w, 0.0);
    EXPECT_NEAR(norm(rotate(a, v)), norm(v), 1e-12);
  }
}

TEST(Mat3, ProductAndTranspose) {
  const Mat3 r = to_matrix(Quat::from_axis_angle(normalized(Vec3{1, 2, 3}), 0.7));
  const Mat3 i = transpose(r) * r;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(i(a, b), a == b ? 1.0 : 0.0, 1e-15);
  }
}

}  // namespace
}  // namespace bushel
