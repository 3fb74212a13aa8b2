// The pair batch (kinematics, law and torques in one vectorised kernel) against the contact
// batch fed with the same contacts' kinematics worked out with Vec3 (the brute-force path).

#include "bushel/contact/contact_batch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "bushel/core/vec3.hpp"

namespace bushel {
namespace {

struct Side {
  Vec3 offset, velocity, spin;  // element centre minus centre of mass [m], [m/s], [rad/s]
  double radius, mass;
};

TEST(PairBatch, MatchesContactBatchWithVec3Kinematics) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto vec = [&](double scale) { return Vec3{u(rng), u(rng), u(rng)} * scale; };
  PairBatch pairs;
  ContactBatch contacts;
  Side si[PairBatch::capacity], sj[PairBatch::capacity];
  Vec3 arm_i[PairBatch::capacity], arm_j[PairBatch::capacity];
  constexpr double dt = 1e-5;
  for (int k = 0; k < PairBatch::capacity; ++k) {
    // Every other contact between lone spheres (offsets exactly zero), the rest clump parts;
    // some with a tangential displacement, some sliding (large tangential speed).
    const bool clump = k % 2 == 1;
    si[k] = {clump ? vec(1e-3) : Vec3{}, vec(0.3), vec(50.0), 1.5e-3 + 0.5e-3 * u(rng), 2e-5};
    sj[k] = {clump ? vec(1e-3) : Vec3{}, vec(k % 3 == 0 ? 3.0 : 0.3), vec(50.0), 1.8e-3, 3e-5};
    const Vec3 n = normalized(vec(1.0));
    const double overlap = 1e-5 * (1.0 + u(rng));
    const Vec3 d = (si[k].radius + sj[k].radius - overlap) * n;
    pairs.dx[k] = d.x, pairs.dy[k] = d.y, pairs.dz[k] = d.z;
    pairs.ri[k] = si[k].radius, pairs.rj[k] = sj[k].radius;
    pairs.oix[k] = si[k].offset.x, pairs.oiy[k] = si[k].offset.y, pairs.oiz[k] = si[k].offset.z;
    pairs.ojx[k] = sj[k].offset.x, pairs.ojy[k] = sj[k].offset.y, pairs.ojz[k] = sj[k].offset.z;
    pairs.vix[k] = si[k].velocity.x, pairs.viy[k] = si[k].velocity.y, pairs.viz[k] = si[k].velocity.z;
    pairs.vjx[k] = sj[k].velocity.x, pairs.vjy[k] = sj[k].velocity.y, pairs.vjz[k] = sj[k].velocity.z;
    pairs.wix[k] = si[k].spin.x, pairs.wiy[k] = si[k].spin.y, pairs.wiz[k] = si[k].spin.z;
    pairs.wjx[k] = sj[k].spin.x, pairs.wjy[k] = sj[k].spin.y, pairs.wjz[k] = sj[k].spin.z;
    pairs.mi[k] = si[k].mass, pairs.mj[k] = sj[k].mass;
    const Vec3 xi = k % 4 == 1 ? vec(2e-6) : Vec3{};
    pairs.xi_x[k] = contacts.xi_x[k] = xi.x;
    pairs.xi_y[k] = contacts.xi_y[k] = xi.y;
    pairs.xi_z[k] = contacts.xi_z[k] = xi.z;
    pairs.youngs_modulus[k] = contacts.youngs_modulus[k] = 1.4e7;
    pairs.stiffness_ratio[k] = contacts.stiffness_ratio[k] = 0.87;
    pairs.root_stiffness_ratio[k] = contacts.root_stiffness_ratio[k] = std::sqrt(0.87);
    pairs.damping[k] = contacts.damping[k] = 0.48;
    pairs.static_friction[k] = contacts.static_friction[k] = 0.27;

    // The same contact through Vec3: normal and overlap from the centres, contact point
    // c = x_i + (r_i - delta/2) n, arms from each centre of mass, velocity of i's point minus j's.
    const double dist = norm(d);
    const Vec3 normal = d / dist;
    const double delta = si[k].radius + sj[k].radius - dist;
    arm_i[k] = si[k].offset + (si[k].radius - 0.5 * delta) * normal;
    arm_j[k] = sj[k].offset - (sj[k].radius - 0.5 * delta) * normal;
    const Vec3 v = si[k].velocity + cross(si[k].spin, arm_i[k]) - sj[k].velocity - cross(sj[k].spin, arm_j[k]);
    contacts.nx[k] = normal.x, contacts.ny[k] = normal.y, contacts.nz[k] = normal.z;
    contacts.overlap[k] = delta;
    contacts.vx[k] = v.x, contacts.vy[k] = v.y, contacts.vz[k] = v.z;
    contacts.r_star[k] = si[k].radius * sj[k].radius / (si[k].radius + sj[k].radius);
    contacts.m_star[k] = si[k].mass * sj[k].mass / (si[k].mass + sj[k].mass);
  }
  pairs.size = contacts.size = PairBatch::capacity;
  pairs.centred = false;   // half of them are clump parts
  PairBatch lone = pairs;  // all at their centres of mass (below)
  solve(pairs, dt);
  solve(contacts, dt);

  int sliding = 0;
  for (int k = 0; k < PairBatch::capacity; ++k) {
    SCOPED_TRACE(k);
    const Vec3 f{contacts.fx[k], contacts.fy[k], contacts.fz[k]};
    const double scale = std::max(norm(f), 1e-2);  // [N]; a contact flying apart may have none
    const double tol = 1e-12 * scale;
    EXPECT_NEAR(pairs.fx[k], f.x, tol);
    EXPECT_NEAR(pairs.fy[k], f.y, tol);
    EXPECT_NEAR(pairs.fz[k], f.z, tol);
    EXPECT_NEAR(pairs.normal_force[k], contacts.normal_force[k], 1e-12 * contacts.normal_force[k]);
    const Vec3 t_i = cross(arm_i[k], f), t_j = cross(arm_j[k], -f);
    const double torque_tol = 1e-12 * scale * 4e-3;
    EXPECT_NEAR(pairs.tix[k], t_i.x, torque_tol);
    EXPECT_NEAR(pairs.tiy[k], t_i.y, torque_tol);
    EXPECT_NEAR(pairs.tiz[k], t_i.z, torque_tol);
    EXPECT_NEAR(pairs.tjx[k], t_j.x, torque_tol);
    EXPECT_NEAR(pairs.tjy[k], t_j.y, torque_tol);
    EXPECT_NEAR(pairs.tjz[k], t_j.z, torque_tol);
    EXPECT_NEAR(pairs.arm_i[k], norm(arm_i[k]), 1e-15);
    EXPECT_NEAR(pairs.arm_j[k], norm(arm_j[k]), 1e-15);
    EXPECT_NEAR(pairs.xi_x[k], contacts.xi_x[k], 1e-18);
    EXPECT_NEAR(pairs.xi_y[k], contacts.xi_y[k], 1e-18);
    EXPECT_NEAR(pairs.xi_z[k], contacts.xi_z[k], 1e-18);
    EXPECT_NEAR(pairs.overlap[k], contacts.overlap[k], 1e-18);
    if (k % 2 == 0) {  // lone spheres: the same operations in the same order, the same bits
      EXPECT_EQ(pairs.fx[k], f.x);
      EXPECT_EQ(pairs.fy[k], f.y);
      EXPECT_EQ(pairs.fz[k], f.z);
    }
    const double f_t = norm(f + contacts.normal_force[k] * Vec3{contacts.nx[k], contacts.ny[k], contacts.nz[k]});
    if (f_t >= 0.27 * contacts.normal_force[k] * (1.0 - 1e-9)) ++sliding;
  }
  EXPECT_GT(sliding, 0);  // the Coulomb cut was exercised
  EXPECT_LT(sliding, PairBatch::capacity);

  // With every offset zero, the centred kernel (arm lengths without a square root) gives the
  // same as the general one.
  for (int k = 0; k < PairBatch::capacity; ++k) {
    lone.oix[k] = lone.oiy[k] = lone.oiz[k] = lone.ojx[k] = lone.ojy[k] = lone.ojz[k] = 0.0;
  }
  PairBatch general = lone;
  solve(general, dt);
  lone.centred = true;
  solve(lone, dt);
  for (int k = 0; k < PairBatch::capacity; ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(lone.fx[k], general.fx[k]);
    EXPECT_EQ(lone.tjz[k], general.tjz[k]);
    EXPECT_EQ(lone.xi_y[k], general.xi_y[k]);
    EXPECT_NEAR(lone.arm_i[k], general.arm_i[k], 1e-15 * general.arm_i[k]);
    EXPECT_NEAR(lone.arm_j[k], general.arm_j[k], 1e-15 * general.arm_j[k]);
  }
}

}  // namespace
}  // namespace bushel
