// The clumps' orientation step in lanes (vectorised, built for several instruction sets)
// against the one-clump step: the same bits for every clump, at any batch size.

#include "bushel/integrate/rotation_batch.hpp"

#include <gtest/gtest.h>

#include <random>

#include "bushel/integrate/rigid_rotation.hpp"

namespace bushel {
namespace {

struct Clump {
  Quat q;
  Vec3 inverse_inertia, momentum, omega;  // [1/(kg m2)], [kg m2/s], [rad/s]
};

TEST(RotationBatch, GivesEveryClumpTheBitsOfTheOneClumpStep) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), positive(0.5, 4.0);
  constexpr double dt = 4e-6;  // [s]
  for (const int n : {1, 7, RotationBatch::capacity}) {
    RotationBatch batch;
    std::vector<Clump> clumps(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
      Clump& c = clumps[static_cast<std::size_t>(k)];
      c.q = normalized(Quat{u(rng), u(rng), u(rng), u(rng)});
      // A wheat kernel's moments (about 1e-9 kg m2), elongated; spins up to several
      // thousand rad/s, so that a step turns the clump visibly.
      c.inverse_inertia = Vec3{positive(rng), positive(rng), positive(rng)} * 1e9;
      c.momentum = Vec3{u(rng), u(rng), u(rng)} * (k % 2 == 0 ? 1e-6 : 1e-9);
      c.omega = angular_velocity_from_momentum(c.q, c.inverse_inertia, c.momentum);
      batch.qw[k] = c.q.w, batch.qx[k] = c.q.x, batch.qy[k] = c.q.y, batch.qz[k] = c.q.z;
      batch.wx[k] = c.omega.x, batch.wy[k] = c.omega.y, batch.wz[k] = c.omega.z;
      batch.ix[k] = c.inverse_inertia.x, batch.iy[k] = c.inverse_inertia.y, batch.iz[k] = c.inverse_inertia.z;
      batch.lx[k] = c.momentum.x, batch.ly[k] = c.momentum.y, batch.lz[k] = c.momentum.z;
    }
    batch.size = n;
    rotate_rigid(batch, dt);
    for (int k = 0; k < n; ++k) {
      Clump c = clumps[static_cast<std::size_t>(k)];
      const Quat before = c.q;
      rotate_rigid(c.q, c.inverse_inertia, c.momentum, c.omega, dt);
      SCOPED_TRACE(testing::Message() << "batch of " << n << ", clump " << k);
      EXPECT_NE(c.q, before);  // (the step turns every clump)
      EXPECT_EQ(batch.qw[k], c.q.w);
      EXPECT_EQ(batch.qx[k], c.q.x);
      EXPECT_EQ(batch.qy[k], c.q.y);
      EXPECT_EQ(batch.qz[k], c.q.z);
    }
  }
}

}  // namespace
}  // namespace bushel
