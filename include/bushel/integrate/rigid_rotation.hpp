#pragma once
// Rotation of a rigid body with principal inertia (physics.md section 4): angular momentum
// is advanced by the torque in the world frame; the orientation follows with the Richardson
// scheme used for rigid bodies in LAMMPS/LIGGGHTS (a full step combined with two half steps,
// second order), and the angular velocity is recovered from the momentum at the new pose.
// The momentum is the stored state (ParticleSystem::angular_momentum; spin_momentum() gives
// it from an angular velocity), so a step converts between the two as little as possible.

#include "bushel/core/quat.hpp"
#include "bushel/core/vec3.hpp"

namespace bushel {

/// omega = R I^-1 R^T L for principal moments `inertia` and orientation q.
inline Vec3 angular_velocity_from_momentum(const Quat& q, const Vec3& inertia, const Vec3& momentum) {
  const Vec3 l = rotate_inverse(q, momentum);
  return rotate(q, Vec3{l.x / inertia.x, l.y / inertia.y, l.z / inertia.z});
}

/// Moment of inertia about the world direction `u` (unit) [kg m2].
inline double inertia_about(const Quat& q, const Vec3& inertia, const Vec3& u) {
  const Vec3 b = rotate_inverse(q, u);
  return inertia.x * b.x * b.x + inertia.y * b.y * b.y + inertia.z * b.z * b.z;
}

/// dq = dt/2 (0, omega) q, normalised.
inline Quat advance(const Quat& q, const Vec3& omega, double dt) {
  const Quat wq = Quat{0.0, omega.x, omega.y, omega.z} * q;
  const double h = 0.5 * dt;
  return normalized(Quat{q.w + h * wq.w, q.x + h * wq.x, q.y + h * wq.y, q.z + h * wq.z});
}

/// Advances q over dt at constant angular momentum L, given the angular velocity `w0` that L
/// has at the current q; returns the new angular velocity.
inline Vec3 rotate_rigid(Quat& q, const Vec3& inertia, const Vec3& momentum, const Vec3& w0, double dt) {
  const Quat full = advance(q, w0, dt);
  const Quat half = advance(q, w0, 0.5 * dt);
  const Quat half2 = advance(half, angular_velocity_from_momentum(half, inertia, momentum), 0.5 * dt);
  q = normalized(Quat{2 * half2.w - full.w, 2 * half2.x - full.x, 2 * half2.y - full.y, 2 * half2.z - full.z});
  return angular_velocity_from_momentum(q, inertia, momentum);
}

}  // namespace bushel
