#pragma once
// Rolling resistance sub-models (docs/physics.md section 2, "Rolling resistance"). Each declares
// its name, how many history values it keeps and whether it reads the spins; the contact loop
// is compiled once per model (no virtual call per contact). To add a model: write a struct
// like these and list it in RollingModel (contact_model.hpp).

#include <algorithm>
#include <cmath>

#include "bushel/core/vec3.hpp"

namespace bushel {

/// What a rolling model receives about one contact.
struct RollingInput {
  Vec3 normal;              ///< unit normal from i to j
  Vec3 omega_i, omega_j;    ///< angular velocities of the two bodies (world) [rad/s]
  double arm_i, arm_j;      ///< distance from the contact point to each centre of mass [m]
  double r_star;            ///< effective radius R* [m]
  double normal_force;      ///< F_n >= 0 [N]
  double normal_stiffness;  ///< S_n [N/m]
  double overlap;           ///< delta [m]
  double mu_r;              ///< rolling friction coefficient [-]
  double inertia_r;         ///< effective rolling inertia (EPSD damping) [kg m2]
  double dt;                ///< [s]
};

/// What it returns: a torque vector on each side, and the magnitudes of constant
/// directional torques that the integrator applies against each body's own spin.
struct RollingOutput {
  Vec3 torque_i, torque_j;  ///< [N m]
  double cdt_i = 0.0;       ///< |tau| opposing omega_i [N m]
  double cdt_j = 0.0;       ///< |tau| opposing omega_j [N m]
};

struct NoRolling {
  static constexpr const char* name = "none";
  static constexpr int history_size = 0;
  static constexpr bool uses_spin = false;     ///< reads omega_i, omega_j
  static constexpr bool has_torque = false;    ///< returns torque vectors (else only cdt_i, cdt_j)
  static constexpr bool uses_inertia = false;  ///< reads inertia_r (computed only for models that do)
  static RollingOutput torque(const RollingInput&, Vec3&) { return {}; }
};

/// Constant directional torque (EDEM "standard rolling friction"):
/// tau_i = -mu_r |F_n| R_i omega_i / |omega_i|, with each body's own spin. The magnitude is
/// handed to the integrator, which caps it so it can stop a spin but never reverse it within
/// a step: the guard against the sign flipping at rest.
struct CdtRolling {
  static constexpr const char* name = "cdt";
  static constexpr int history_size = 0;
  static constexpr bool uses_spin = false;  // the integrator applies it against each spin
  static constexpr bool has_torque = false;
  static constexpr bool uses_inertia = false;
  static RollingOutput torque(const RollingInput& in, Vec3&) {
    RollingOutput out;
    out.cdt_i = in.mu_r * in.normal_force * in.arm_i;
    out.cdt_j = in.mu_r * in.normal_force * in.arm_j;
    return out;
  }
};

/// Elastic-plastic spring-dashpot (Ai et al. 2011, model type C): a rolling spring
/// k_r = 2.25 S_n (mu_r R*)^2 on the relative rolling rotation, capped at mu_r R* F_n, with
/// viscous damping 2 eta_r sqrt(I_r k_r) while the spring is below the cap.
struct EpsdRolling {
  static constexpr const char* name = "epsd";
  static constexpr int history_size = 3;
  static constexpr bool uses_spin = true;
  static constexpr bool has_torque = true;
  static constexpr bool uses_inertia = true;
  static constexpr double damping_ratio = 0.3;  ///< eta_r, Ai et al.'s recommended value
  static RollingOutput torque(const RollingInput& in, Vec3& spring) {
    Vec3 w = in.omega_i - in.omega_j;
    w -= dot(w, in.normal) * in.normal;  // twisting is not rolling
    const double k_r = 2.25 * in.normal_stiffness * (in.mu_r * in.r_star) * (in.mu_r * in.r_star);
    // Keep the spring in the current tangent plane, as the tangential displacement.
    const double len = norm(spring);
    if (len > 0.0) {
      spring -= dot(spring, in.normal) * in.normal;
      const double p = norm(spring);
      spring = p > 0.0 ? spring * (len / p) : Vec3{};
    }
    spring -= k_r * in.dt * w;
    const double cap = in.mu_r * in.r_star * in.normal_force;
    const double s = norm(spring);
    Vec3 m = spring;
    if (s > cap) {
      spring = spring * (cap / s);
      m = spring;
    } else {
      m -= 2.0 * damping_ratio * std::sqrt(in.inertia_r * k_r) * w;
    }
    return {m, -m, 0.0, 0.0};
  }
};

/// LIGGGHTS's constant directional torque (`rolling_friction cdt`): a torque against the
/// relative spin of the two bodies, tau_i = -tau_j = -mu_r F_e R* w_t / |w_t|, with
/// w = omega_i - omega_j, w_t its part in the tangent plane (the torque's twisting part is
/// removed), R* = r_i r_j / (r_i + r_j) (the sphere's radius against a part) and
/// F_e = 2/3 S_n delta the elastic normal force (LIGGGHTS's k_n delta_n). Unlike `cdt`, the
/// arm is R* rather than each body's own arm, it acts on the relative spin, and it is applied
/// as a torque: nothing stops it from reversing a spin within a step.
struct LiggghtsCdtRolling {
  static constexpr const char* name = "liggghts_cdt";
  static constexpr int history_size = 0;
  static constexpr bool uses_spin = true;
  static constexpr bool has_torque = true;
  static constexpr bool uses_inertia = false;
  static RollingOutput torque(const RollingInput& in, Vec3&) {
    const Vec3 w = in.omega_i - in.omega_j;
    const double spin = norm(w);
    if (!(spin > 0.0)) return {};
    const double elastic = 2.0 / 3.0 * in.normal_stiffness * in.overlap;
    Vec3 t = (in.mu_r * elastic * in.r_star / spin) * w;
    t -= dot(t, in.normal) * in.normal;
    return {-1.0 * t, t, 0.0, 0.0};
  }
};

}  // namespace bushel
