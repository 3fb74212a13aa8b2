#pragma once
// The orientation step of many rigid clumps at once (rigid_rotation.hpp: Richardson's
// scheme). Per clump it is a chain of dependent square roots and divisions (four
// normalisations), so one clump at a time leaves the processor waiting on their latency; in
// structure-of-arrays form the compiler runs several clumps per instruction (SSE2, or AVX2 or
// AVX-512 where the processor has them). The lanes call the same function as the one-clump
// step, with only IEEE add, multiply, divide and square root and no fused multiply-add, so
// every clump gets the same bits either way. (The rotation matrix and the new angular
// velocity are left to the caller: a matrix in the lanes keeps GCC 12 from vectorising.)

namespace bushel {

/// Clumps in structure-of-arrays form, for rotate_rigid(RotationBatch&, double).
struct RotationBatch {
  static constexpr int capacity = 64;
  int size = 0;  ///< clumps in use

  /// in: orientation (unit quaternion); out: the orientation dt later
  double qw[capacity], qx[capacity], qy[capacity], qz[capacity];

  // --- in ---------------------------------------------------------------------------------
  double wx[capacity], wy[capacity], wz[capacity];  ///< angular velocity at the orientation in [rad/s]
  double ix[capacity], iy[capacity], iz[capacity];  ///< inverse principal moments [1/(kg m2)]
  double lx[capacity], ly[capacity], lz[capacity];  ///< angular momentum, world frame [kg m2/s]
};

/// Advances the orientation of every clump of the batch over dt [s] at constant angular
/// momentum, as the one-clump rotate_rigid (rigid_rotation.hpp) does.
void rotate_rigid(RotationBatch& batch, double dt);

}  // namespace bushel
