#pragma once
// The largest stable time step of a scene's contacts, from the contact stiffness and the
// effective mass at the contact point, translation and rotation together (docs/physics.md
// section 3). Unlike the Rayleigh step of the smallest element, it knows that a clump's
// element carries the whole clump, and that a contact point can also move by turning.

#include <limits>
#include <string>
#include <vector>

#include "bushel/contact/contact_table.hpp"
#include "bushel/contact/pair_coefficients.hpp"
#include "bushel/geometry/part.hpp"
#include "bushel/particles/particle_type.hpp"

namespace bushel {

/// One side of a contact: a sphere element of a body, or a wall (the defaults). A force F at
/// the contact point moves it by F (1/mass + turning) per unit time squared: the body's
/// translation and its rotation about its centre of mass.
struct ContactSide {
  double radius = std::numeric_limits<double>::infinity();  ///< the element's radius [m]
  double mass = std::numeric_limits<double>::infinity();    ///< its body's mass [kg]
  /// Largest rotational inverse mass along the contact normal [1/kg]: max over unit n of
  /// (d x n)^T I^-1 (d x n), d the element's centre from the body's centre of mass, I the
  /// body's inertia (exact: the largest eigenvalue of [d]x^T I^-1 [d]x).
  double normal_turning = 0.0;
  /// The same across the normal, at the contact point c = d + r n [1/kg]: max over unit n
  /// and t across it of (c x t)^T I^-1 (c x t), by a search over the directions, at most the
  /// bound (sqrt(normal_turning) + r sqrt(1 / I_min))^2 (2.5/m for a lone sphere).
  double tangential_turning = 0.0;
};

/// The sides of each sphere element of a type, in element order.
std::vector<ContactSide> contact_sides(const ParticleType& type);

/// A stable step and the contact mode that sets it.
struct CriticalStep {
  double dt = std::numeric_limits<double>::infinity();  ///< [s]
  double omega = 0.0;                                   ///< angular frequency of the mode [rad/s]
  double zeta = 0.0;                                    ///< damping ratio of the mode [-]
  bool tangential = false;                              ///< the tangential mode (else the normal one)
  std::string pair;                                     ///< the species in contact, e.g. "large-large" or "large-cup"
};

/// The overlap at which the stiffness is taken, over the smaller radius [-]: the deepest
/// overlap a run accepts without a warning (run_warnings.cpp), where Hertz is stiffest.
inline constexpr double critical_step_overlap = 0.05;

/// The two modes of one contact, normal and tangential: for each the central-difference limit
/// dt = 2 (sqrt(1 + zeta^2) - zeta) / omega, omega^2 = S / m_mode, with S the Hertz (S_n) or
/// Mindlin (S_t) stiffness at `overlap_ratio` of the smaller radius.
struct ContactModes {
  CriticalStep normal, tangential;
};
ContactModes contact_modes(const ContactSide& i, const ContactSide& j, const PairCoefficients& c,
                           double overlap_ratio = critical_step_overlap);

/// The critical step of one contact: the shorter of its two modes'.
CriticalStep critical_step(const ContactSide& i, const ContactSide& j, const PairCoefficients& c,
                           double overlap_ratio = critical_step_overlap);

/// The smallest critical step over every pair of elements of `types` and every element with
/// every part, with the contact table's restitution for each pair. Throws InputError where
/// the table does not resolve (as the run would).
CriticalStep critical_time_step(const std::vector<ParticleType>& types, const std::vector<Part>& parts,
                                const ContactTable& table, double overlap_ratio = critical_step_overlap);

}  // namespace bushel
