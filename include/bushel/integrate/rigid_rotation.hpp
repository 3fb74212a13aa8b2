#pragma once
// Rotation of a rigid body with principal inertia (docs/physics.md section 4): angular momentum
// is advanced by the torque in the world frame; the orientation follows with the Richardson
// scheme used for rigid bodies in LAMMPS/LIGGGHTS (a full step combined with two half steps,
// second order), and the angular velocity is recovered from the momentum at the new pose.
// The momentum is the stored state (ParticleSystem::angular_momentum; spin_momentum() gives
// it from an angular velocity), so a step converts between the two as little as possible.
// The principal moments enter as their inverses (ParticleSystem::inverse_inertia): the step
// multiplies instead of dividing.

#include "bushel/core/mat3.hpp"
#include "bushel/core/quat.hpp"
#include "bushel/core/vec3.hpp"

namespace bushel {

/// Componentwise product: a diagonal matrix (principal moments or their inverses) times v.
constexpr Vec3 scale(const Vec3& diagonal, const Vec3& v) {
  return {diagonal.x * v.x, diagonal.y * v.y, diagonal.z * v.z};
}

/// omega = R I^-1 R^T L for inverse principal moments `inverse_inertia` [1/(kg m2)] and
/// orientation q.
inline Vec3 angular_velocity_from_momentum(const Quat& q, const Vec3& inverse_inertia, const Vec3& momentum) {
  return rotate(q, scale(inverse_inertia, rotate_inverse(q, momentum)));
}

/// The same with the orientation as a rotation matrix, for a caller that has it at hand.
constexpr Vec3 angular_velocity_from_momentum(const Mat3& r, const Vec3& inverse_inertia, const Vec3& momentum) {
  return r * scale(inverse_inertia, transpose_times(r, momentum));
}

/// dq = dt/2 (0, omega) q, normalised.
inline Quat advance(const Quat& q, const Vec3& omega, double dt) {
  const Quat wq = Quat{0.0, omega.x, omega.y, omega.z} * q;
  const double h = 0.5 * dt;
  return normalized(Quat{q.w + h * wq.w, q.x + h * wq.x, q.y + h * wq.y, q.z + h * wq.z});
}

/// Advances q over dt at constant angular momentum L, given the angular velocity `w0` that L
/// has at the current q. The caller recovers the new angular velocity at the new q.
inline void rotate_rigid(Quat& q, const Vec3& inverse_inertia, const Vec3& momentum, const Vec3& w0, double dt) {
  const Quat full = advance(q, w0, dt);
  const Quat half = advance(q, w0, 0.5 * dt);
  const Quat half2 = advance(half, angular_velocity_from_momentum(half, inverse_inertia, momentum), 0.5 * dt);
  q = normalized(Quat{2 * half2.w - full.w, 2 * half2.x - full.x, 2 * half2.y - full.y, 2 * half2.z - full.z});
}

}  // namespace bushel
