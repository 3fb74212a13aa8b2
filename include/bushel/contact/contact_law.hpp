#pragma once
// The contact law as sub-models (docs/physics.md section 2; docs/engine.md, "Contact law"):
// normal (Hertz), damping (EDEM's viscoelastic), tangential (Mindlin no-slip with a Coulomb
// cut) and rolling (rolling_models.hpp, chosen by name in contact_model.hpp). Each is a struct
// of stateless functions on one contact's numbers, which the lane kernels of contact_batch.cpp
// call inside their vectorised loops; `HertzMindlin` composes them. A sub-model's coefficients
// are fields of PairCoefficients (pair_coefficients.hpp), resolved once per pair of species,
// and reach the lanes through LawLanes below, the one list of what the law reads per contact.
//
// Adding a normal, damping or tangential model is a struct like these and its use in a law
// like HertzMindlin; a rolling model is a struct and a line in RollingModel.

#include <cmath>

#include "bushel/contact/pair_coefficients.hpp"

namespace bushel {

/// Hertz: S_n = 2 E* sqrt(R* delta), elastic force 2/3 S_n delta = 4/3 E* sqrt(R*) delta^(3/2).
struct HertzNormal {
  /// S_n [N/m] from E* [Pa], R* [m] and the overlap delta [m].
  static double stiffness(double youngs_modulus, double r_star, double overlap) {
    return 2.0 * youngs_modulus * std::sqrt(r_star * overlap);
  }
  /// The elastic normal force [N].
  static double elastic_force(double stiffness, double overlap) { return 2.0 / 3.0 * stiffness * overlap; }
};

/// EDEM's viscoelastic damping: gamma sqrt(S_n m*) v_n along the normal and
/// gamma sqrt(k) sqrt(S_n m*) on the tangential velocity, gamma from the restitution
/// (restitution_damping.hpp), the tangential part bounded by the contact's sliding mass
/// (contact_batch.hpp).
struct ViscoelasticDamping {
  /// The normal damping force [N] at approach speed v_n [m/s]; root = sqrt(S_n m*) [kg/s].
  static double normal_force(double damping, double root, double v_n) { return damping * root * v_n; }
  /// The tangential damping coefficient gamma_t [N s/m], at most `limit`.
  static double tangential(double damping, double root_stiffness_ratio, double root, double limit) {
    const double model = damping * root_stiffness_ratio * root;
    return model < limit ? model : limit;
  }
};

/// Mindlin no-slip: a tangential spring S_t = k S_n on the displacement xi (3 history values),
/// cut to mu_s F_n; sliding, the spring holds the Coulomb force alone.
struct MindlinTangential {
  static constexpr int history_size = 3;
  /// Turns xi into the tangent plane of unit normal n, keeping its length, and adds the
  /// step's tangential displacement t dt.
  static void rotate_and_stretch(double& x, double& y, double& z, double nx, double ny, double nz, double tx, double ty,
                                 double tz, double dt) {
    const double len2 = x * x + y * y + z * z;
    const double along = x * nx + y * ny + z * nz;
    const double projected2 = len2 - along * along;
    const double keep = along != 0.0 ? (projected2 > 0.0 ? std::sqrt(len2 / projected2) : 0.0) : 1.0;
    x = (x - along * nx) * keep + tx * dt;
    y = (y - along * ny) * keep + ty * dt;
    z = (z - along * nz) * keep + tz * dt;
  }
};

/// The lanes of the law's coefficients for N contacts: one array per PairCoefficients field
/// that the lane kernel reads.
template <int N>
struct LawLanes {
  double youngs_modulus[N];        ///< E* [Pa]
  double stiffness_ratio[N];       ///< k = S_t / S_n [-]
  double root_stiffness_ratio[N];  ///< sqrt(k) [-]
  double damping[N];               ///< gamma [-]
  double static_friction[N];       ///< mu_s [-]
  /// Lane k's coefficients.
  void set(int k, const PairCoefficients& c) {
    youngs_modulus[k] = c.youngs_modulus;
    stiffness_ratio[k] = c.stiffness_ratio;
    root_stiffness_ratio[k] = c.root_stiffness_ratio;
    damping[k] = c.damping;
    static_friction[k] = c.static_friction;
  }
};

/// What the law needs of one contact besides its history.
struct LawInput {
  double nx, ny, nz;      ///< unit normal from i to j
  double overlap;         ///< delta [m]
  double vx, vy, vz;      ///< velocity of i's contact point minus j's [m/s]
  double r_star, m_star;  ///< R* [m], m* [kg]
  double youngs_modulus, stiffness_ratio, root_stiffness_ratio, damping, static_friction;  ///< LawLanes
  double damping_limit;                                                                    ///< largest gamma_t [N s/m]
};
struct LawOutput {
  double fx, fy, fz;        ///< force on i [N]
  double normal_force;      ///< F_n >= 0 [N]
  double normal_stiffness;  ///< S_n [N/m]
};

/// Hertz-Mindlin with viscoelastic damping (equations in contact_batch.hpp); updates xi.
/// Branch-free: both sides of each choice are computed and one selected, which is safe in
/// files built without math errno and FP trapping (src/CMakeLists.txt); the selected values
/// are those of branches.
struct HertzMindlin {
  [[gnu::always_inline]] static inline LawOutput force(const LawInput& in, double& xi_x, double& xi_y, double& xi_z,
                                                       double dt) {
    const double nx = in.nx, ny = in.ny, nz = in.nz;
    const double v_n = in.vx * nx + in.vy * ny + in.vz * nz;
    const double tx = in.vx - v_n * nx, ty = in.vy - v_n * ny, tz = in.vz - v_n * nz;
    const double s_n = HertzNormal::stiffness(in.youngs_modulus, in.r_star, in.overlap);
    const double root_s_n_m = std::sqrt(s_n * in.m_star);
    const double elastic_damped =
        HertzNormal::elastic_force(s_n, in.overlap) + ViscoelasticDamping::normal_force(in.damping, root_s_n_m, v_n);
    const double f_n = elastic_damped > 0.0 ? elastic_damped : 0.0;
    double x = xi_x, y = xi_y, z = xi_z;
    MindlinTangential::rotate_and_stretch(x, y, z, nx, ny, nz, tx, ty, tz, dt);
    const double s_t = in.stiffness_ratio * s_n;
    const double gamma_t =
        ViscoelasticDamping::tangential(in.damping, in.root_stiffness_ratio, root_s_n_m, in.damping_limit);
    double fx = -s_t * x - gamma_t * tx, fy = -s_t * y - gamma_t * ty, fz = -s_t * z - gamma_t * tz;
    const double limit = in.static_friction * f_n;
    const double f_len2 = fx * fx + fy * fy + fz * fz;
    const bool sliding = f_len2 > limit * limit;
    const double cut = sliding ? limit / std::sqrt(f_len2) : 1.0;
    fx *= cut, fy *= cut, fz *= cut;
    // Sliding: the spring holds the Coulomb force alone (not the damping's share too, which it
    // would give back as the contact point slows: contact_batch.hpp).
    const bool spring = sliding && s_t > 0.0;
    const double inverse_s_t = 1.0 / (s_t > 0.0 ? s_t : 1.0);  // one division for three
    xi_x = spring ? -fx * inverse_s_t : (sliding ? 0.0 : x);
    xi_y = spring ? -fy * inverse_s_t : (sliding ? 0.0 : y);
    xi_z = spring ? -fz * inverse_s_t : (sliding ? 0.0 : z);
    return {-f_n * nx + fx, -f_n * ny + fy, -f_n * nz + fz, f_n, s_n};
  }
};

}  // namespace bushel
