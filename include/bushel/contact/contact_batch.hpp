#pragma once
// Hertz-Mindlin (no slip) with EDEM's damping (docs/physics.md section 2; its sub-models in
// contact_law.hpp), solved for a batch of
// contacts at once. The batch is in structure-of-arrays form and the law is written without
// branches, so the compiler runs several contacts per instruction (SSE2, or AVX2 or AVX-512
// where the processor has them; all give the same bits: only IEEE add, multiply, divide and
// square root, no fused multiply-add). Sphere-sphere and sphere-part contacts both go through
// this law.
//
// Per contact, with delta the overlap, v the relative velocity of i's contact point, n the
// unit normal from i to j, v_n = v . n (approach speed) and v_t = v - v_n n:
//   S_n = 2 E* sqrt(R* delta),  F_n = max(0, 2/3 S_n delta + gamma sqrt(S_n m*) v_n)
//   (2/3 S_n delta = 4/3 E* sqrt(R*) delta^(3/2); net attraction is clamped to zero)
//   xi: rotated into the current tangent plane with its length kept, then xi += v_t dt
//   S_t = k S_n with k = 4 G*/E*,  F_t = -S_t xi - gamma_t v_t
//   gamma_t = min(gamma sqrt(k) sqrt(S_n m*), lambda m_t)
//   where |F_t| > mu_s F_n: F_t cut to mu_s F_n and xi = -F_t / S_t
// The force on i is -F_n n + F_t.
//
// Sliding, the spring holds the Coulomb force alone. Were it to hold the damping's share as
// well, -(F_t + gamma_t v_t) / S_t, it would give that share back as an elastic force when
// the contact point slows: with strong damping (restitution 0.1) a sliding impact then pushed
// the sphere forward and gained energy, and a poured packing came out 3 % denser
// (validation/results/contact-law.md).
//
// lambda = limit / dt bounds the tangential damping by the sliding mass m_t of the contact
// points (1/m_t = 1/m_i + 1/m_j + arm_i^2 / I_i + arm_j^2 / I_j), so that one step takes at most
// the fraction `limit` of their relative tangential velocity. Explicit damping stronger than
// 1/dt overshoots; a body shares it among its contacts and its spin is light (m_t is m*/3.5
// for two spheres), so a resting packing at restitution 0.1 jittered at 0.2 of the Rayleigh
// step without the bound. Contacts that the step resolves are not touched by it.

#include "bushel/contact/contact_law.hpp"

namespace bushel {

/// Contacts whose normal, overlap and relative velocity are known (sphere-part contacts).
struct ContactBatch {
  static constexpr int capacity = 128;
  int size = 0;  ///< contacts in use

  // --- in ---------------------------------------------------------------------------------
  double nx[capacity], ny[capacity], nz[capacity];  ///< unit normal from i to j
  double overlap[capacity];                         ///< delta [m]
  double vx[capacity], vy[capacity], vz[capacity];  ///< velocity of i's contact point minus j's [m/s]
  double r_star[capacity];                          ///< R* [m]
  double m_star[capacity];                          ///< m* [kg]
  LawLanes<capacity> law;                           ///< the law's coefficients
  double compliance[capacity];                      ///< 1/m_t, sliding compliance of the contact point [1/kg]
  // --- in and out -------------------------------------------------------------------------
  double xi_x[capacity], xi_y[capacity], xi_z[capacity];  ///< tangential displacement [m]
  // --- out --------------------------------------------------------------------------------
  double fx[capacity], fy[capacity], fz[capacity];  ///< force on i [N]
  double normal_force[capacity];                    ///< F_n >= 0 [N]
  double normal_stiffness[capacity];                ///< S_n [N/m]
};

/// Solves contacts [0, batch.size) over a time step dt [s]; damping_rate is lambda [1/s]
/// (infinity: no bound).
void solve(ContactBatch& batch, double dt, double damping_rate);

/// Sphere-sphere contacts given by the two spheres and their bodies' motion: the batch also
/// does the kinematics (normal, overlap, arms, relative velocity of the contact point) and the
/// torques, so that all the vector algebra of a contact runs vectorised and the contact loop
/// only gathers and scatters. Element i's centre is at o_i from its body's centre of mass
/// (zero for a lone sphere); the contact point is c = x_i + (r_i - delta/2) n, so the arms
/// are o_i + (r_i - delta/2) n and o_j - (r_j - delta/2) n.
struct PairBatch {
  static constexpr int capacity = 64;
  int size = 0;         ///< contacts in use
  bool centred = true;  ///< every element is at its body's centre of mass (o = 0, not read)
  bool uniform = true;  ///< every contact has lane 0's coefficients (the other lanes' not read)

  // --- in ---------------------------------------------------------------------------------
  double dx[capacity], dy[capacity], dz[capacity];     ///< centre of j minus centre of i [m]
  double ri[capacity], rj[capacity];                   ///< radii [m]
  double oix[capacity], oiy[capacity], oiz[capacity];  ///< centre of i minus its body's centre of mass [m]
  double ojx[capacity], ojy[capacity], ojz[capacity];  ///< the same for j [m]
  double vix[capacity], viy[capacity], viz[capacity];  ///< velocity of i's body [m/s]
  double vjx[capacity], vjy[capacity], vjz[capacity];  ///< velocity of j's body [m/s]
  double wix[capacity], wiy[capacity], wiz[capacity];  ///< angular velocity of i's body [rad/s]
  double wjx[capacity], wjy[capacity], wjz[capacity];  ///< angular velocity of j's body [rad/s]
  double mi[capacity], mj[capacity];                   ///< body masses [kg]
  double ji[capacity], jj[capacity];  ///< largest inverse principal moments [1/(kg m2)] (not read if centred)
  LawLanes<capacity> law;             ///< the law's coefficients (lane 0's only, if uniform)
  // --- in and out -------------------------------------------------------------------------
  double xi_x[capacity], xi_y[capacity], xi_z[capacity];  ///< tangential displacement [m]
  // --- out --------------------------------------------------------------------------------
  double nx[capacity], ny[capacity], nz[capacity];     ///< unit normal from i to j
  double r_star[capacity];                             ///< R* [m]
  double overlap[capacity];                            ///< delta [m]
  double fx[capacity], fy[capacity], fz[capacity];     ///< force on i [N]
  double tix[capacity], tiy[capacity], tiz[capacity];  ///< its torque on i's body, arm_i x F [N m]
  double tjx[capacity], tjy[capacity], tjz[capacity];  ///< the reaction's torque on j's body, arm_j x -F [N m]
  double arm_i[capacity], arm_j[capacity];             ///< arm lengths [m]
  double normal_force[capacity];                       ///< F_n >= 0 [N]
  double normal_stiffness[capacity];                   ///< S_n [N/m]
};

/// Solves touching pairs [0, batch.size) over a time step dt [s]; damping_rate as above.
void solve(PairBatch& batch, double dt, double damping_rate);

}  // namespace bushel
