#pragma once
// Hertz-Mindlin (no slip) with EDEM's damping (physics.md section 2), solved for a batch of
// contacts at once. The batch is in structure-of-arrays form and the law is written without
// branches, so the compiler runs several contacts per instruction (SSE2, or AVX2 where the
// processor has it; both give the same bits: only IEEE add, multiply, divide and square root,
// no fused multiply-add). Sphere-sphere and sphere-wall contacts both go through here.
//
// Per contact, with delta the overlap, v the relative velocity of i's contact point, n the
// unit normal from i to j, v_n = v . n (approach speed) and v_t = v - v_n n:
//   S_n = 2 E* sqrt(R* delta),  F_n = max(0, 2/3 S_n delta + gamma sqrt(S_n m*) v_n)
//   (2/3 S_n delta = 4/3 E* sqrt(R*) delta^(3/2); net attraction is clamped to zero)
//   xi: rotated into the current tangent plane with its length kept, then xi += v_t dt
//   S_t = k S_n with k = 4 G*/E*,  F_t = -S_t xi - gamma sqrt(k) sqrt(S_n m*) v_t
//   where |F_t| > mu_s F_n: F_t cut to mu_s F_n and xi = -(F_t + damping term) / S_t
// The force on i is -F_n n + F_t.

namespace bushel {

struct ContactBatch {
  static constexpr int capacity = 128;
  int size = 0;  ///< contacts in use

  // --- in ---------------------------------------------------------------------------------
  double nx[capacity], ny[capacity], nz[capacity];  ///< unit normal from i to j
  double overlap[capacity];                         ///< delta [m]
  double vx[capacity], vy[capacity], vz[capacity];  ///< velocity of i's contact point minus j's [m/s]
  double r_star[capacity];                          ///< R* [m]
  double m_star[capacity];                          ///< m* [kg]
  double youngs_modulus[capacity];                  ///< E* [Pa]
  double stiffness_ratio[capacity];                 ///< k = S_t / S_n [-]
  double root_stiffness_ratio[capacity];            ///< sqrt(k) [-]
  double damping[capacity];                         ///< gamma [-]
  double static_friction[capacity];                 ///< mu_s [-]
  // --- in and out -------------------------------------------------------------------------
  double xi_x[capacity], xi_y[capacity], xi_z[capacity];  ///< tangential displacement [m]
  // --- out --------------------------------------------------------------------------------
  double fx[capacity], fy[capacity], fz[capacity];  ///< force on i [N]
  double normal_force[capacity];                    ///< F_n >= 0 [N]
  double normal_stiffness[capacity];                ///< S_n [N/m]
};

/// Solves contacts [0, batch.size) over a time step dt [s].
void solve(ContactBatch& batch, double dt);

}  // namespace bushel
