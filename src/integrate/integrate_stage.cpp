// The integrate stage: symplectic Euler or velocity Verlet as kicks and drifts; clumps turn by
// the quaternion rigid rotation (rigid_rotation.hpp), in vectorised batches (rotation_batch.hpp).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "bushel/core/parallel.hpp"
#include "bushel/integrate/rigid_rotation.hpp"
#include "bushel/integrate/rotation_batch.hpp"
#include "stages.hpp"

namespace bushel::engine {
namespace {

// Equal principal moments (a sphere): L = I omega in any frame, so rotation needs no quaternion work.
bool is_isotropic(const Vec3& i) { return i.x == i.y && i.y == i.z; }

}  // namespace

void kick(ParticleSystem& ps, const ContactSums& sums, double dt) {
  const auto nb = static_cast<std::ptrdiff_t>(ps.bodies());
#pragma omp parallel for schedule(static) if (parallel_work(ps))
  for (std::ptrdiff_t sb = 0; sb < nb; ++sb) {
    const auto b = static_cast<std::size_t>(sb);
    const Vec3 &force = body_force(ps, sums, b), &torque = body_torque(ps, sums, b);
    const double rolling_resistance = body_rolling_resistance(ps, sums, b);
    ps.velocity[b] += force * (dt / ps.mass(b));
    const Vec3& inv_inertia = ps.inverse_inertia(b);
    const Vec3 omega = ps.angular_velocity[b];
    const double w0 = norm(omega);
    const bool resisted = rolling_resistance > 0.0 && w0 > 0.0;
    if (is_isotropic(ps.inertia(b))) {  // same cap as below, in omega instead of L
      Vec3 w = omega + torque * (dt * inv_inertia.x);
      if (resisted) {
        const Vec3 u = omega / w0;
        const double along = dot(w, u);
        if (along > 0.0) w -= std::min(rolling_resistance * dt * inv_inertia.x, along) * u;
      }
      ps.angular_velocity[b] = w;
      if (ps.keeps_rotation()) ps.angular_momentum[b] = ps.inertia(b).x * w;
      continue;
    }
    // One rotation matrix serves every frame change: momentum, spin direction and the new
    // angular velocity. The cap is linear in L, so it is applied in both frames at once.
    const Mat3 r = to_matrix(ps.orientation[b]);
    Vec3 l = ps.angular_momentum[b] + torque * dt;
    Vec3 l_body = transpose_times(r, l);
    // Constant directional rolling torque against the body's own spin, capped so that it can
    // stop the spin within this step but never reverse it (docs/physics.md section 2: the CDT sign flip).
    if (resisted) {
      const Vec3 u = omega / w0;
      const Vec3 u_body = transpose_times(r, u);
      const double along = dot(scale(inv_inertia, l_body), u_body);  // new spin along u [rad/s]
      if (along > 0.0) {
        const double inertia_u = dot(scale(ps.inertia(b), u_body), u_body);  // moment about u [kg m2]
        const double dl = std::min(rolling_resistance * dt, along * inertia_u);
        l -= dl * u;
        l_body -= dl * u_body;
      }
    }
    ps.angular_momentum[b] = l;
    ps.angular_velocity[b] = r * scale(inv_inertia, l_body);
  }
}

Displacements drift(ParticleSystem& ps, const NeighborList& neighbors, double dt) {
  const std::size_t nb = ps.bodies();
  constexpr std::size_t block = RotationBatch::capacity;
  const auto blocks = static_cast<std::ptrdiff_t>((nb + block - 1) / block);
  double excess = -std::numeric_limits<double>::infinity();  // the most an element has moved past its margin
                                                             // (NeighborList::excess2) [m2]
#pragma omp parallel for schedule(static) reduction(max : excess) if (parallel_work(ps))
  for (std::ptrdiff_t k0 = 0; k0 < blocks; ++k0) {
    // The elements are measured against their margins in the neighbour list while at hand
    // (declared in the loop so that it updates this thread's copy of excess).
    const auto measure = [&](std::uint32_t s, const Vec3& p) {
      excess = std::max(excess, neighbors.excess2(s, neighbors.displacement2(s, p)));
    };
    // The block's clumps with anisotropic inertia rotate together (rotation_batch.hpp); each
    // body's result does not depend on which others share its batch.
    RotationBatch batch;
    std::array<std::size_t, block> body;
    int n = 0;
    const std::size_t b0 = static_cast<std::size_t>(k0) * block, b1 = std::min(nb, b0 + block);
    for (std::size_t b = b0; b < b1; ++b) {
      ps.position[b] += ps.velocity[b] * dt;
      // A lone sphere's orientation changes nothing, so it is not advanced (as LIGGGHTS's
      // nve/sphere).
      if (ps.sphere_count[b] == 1) {
        ps.place_elements(b, measure);
        continue;
      }
      Quat& q = ps.orientation[b];
      if (is_isotropic(ps.inertia(b))) {
        q = advance(q, ps.angular_velocity[b], dt);  // omega is constant
        ps.place_elements(b, to_matrix(q), measure);
        continue;
      }
      const Vec3 &w = ps.angular_velocity[b], &ii = ps.inverse_inertia(b), &l = ps.angular_momentum[b];
      batch.qw[n] = q.w, batch.qx[n] = q.x, batch.qy[n] = q.y, batch.qz[n] = q.z;
      batch.wx[n] = w.x, batch.wy[n] = w.y, batch.wz[n] = w.z;
      batch.ix[n] = ii.x, batch.iy[n] = ii.y, batch.iz[n] = ii.z;
      batch.lx[n] = l.x, batch.ly[n] = l.y, batch.lz[n] = l.z;
      body[static_cast<std::size_t>(n++)] = b;
    }
    batch.size = n;
    if (n > 0) rotate_rigid(batch, dt);
    for (int k = 0; k < n; ++k) {
      const std::size_t b = body[static_cast<std::size_t>(k)];
      ps.orientation[b] = {batch.qw[k], batch.qx[k], batch.qy[k], batch.qz[k]};
      const Mat3 r = to_matrix(ps.orientation[b]);
      ps.angular_velocity[b] = angular_velocity_from_momentum(r, ps.inverse_inertia(b), ps.angular_momentum[b]);
      ps.place_elements(b, r, measure);
    }
  }
  return neighbors.needs_rebuild(excess) ? Displacements::past_skin : Displacements::within_skin;
}

}  // namespace bushel::engine
