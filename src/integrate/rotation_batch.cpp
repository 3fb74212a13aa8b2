#include "bushel/integrate/rotation_batch.hpp"

#include "bushel/core/vector_clones.hpp"
#include "bushel/integrate/rigid_rotation.hpp"

namespace bushel {

// (flatten: the one-clump functions inlined into the lane loop, else it does not vectorise)
[[gnu::flatten]] BUSHEL_VECTOR_CLONES void rotate_rigid(RotationBatch& b, double dt) {
  const int n = b.size;
#pragma omp simd
  for (int k = 0; k < n; ++k) {
    Quat q{b.qw[k], b.qx[k], b.qy[k], b.qz[k]};
    rotate_rigid(q, {b.ix[k], b.iy[k], b.iz[k]}, {b.lx[k], b.ly[k], b.lz[k]}, {b.wx[k], b.wy[k], b.wz[k]}, dt);
    b.qw[k] = q.w, b.qx[k] = q.x, b.qy[k] = q.y, b.qz[k] = q.z;
  }
}

}  // namespace bushel
