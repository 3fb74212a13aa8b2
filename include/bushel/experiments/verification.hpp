#pragma once
// The analytic checks of docs/physics.md section 7 as small scenes, written once and run by
// `bushel verify`, by the test suite (with the tolerances stated here) and by anyone who
// changes a contact law.

#include <string>
#include <vector>

namespace bushel::verification {

struct CheckResult {
  std::string check;     ///< e.g. "restitution sphere-sphere e=0.5 v=1 m/s"
  std::string quantity;  ///< what is compared, with its unit
  double expected = 0.0;
  double measured = 0.0;
  double tolerance = 0.0;  ///< on the relative error, or on the absolute value where expected is 0
  bool pass = false;

  /// |measured - expected| / |expected|, or |measured| when expected is 0.
  double error() const;
};

struct Options {
  bool quick = false;  ///< fewer cases and steps (the test suite); the full set is `bushel verify`
};

std::vector<CheckResult> restitution(const Options& o);          ///< sphere-sphere and sphere-wall, e x speed
std::vector<CheckResult> hertz_contact_time(const Options& o);   ///< e = 1, vs the analytic duration
std::vector<CheckResult> energy_conservation(const Options& o);  ///< e = 1, no friction, no gravity
std::vector<CheckResult> oblique_impact(const Options& o);       ///< sliding and rolling rebound, Coulomb friction
std::vector<CheckResult> incline(const Options& o);              ///< stick below atan(mu_s), slide above
std::vector<CheckResult> rolling_friction(const Options& o);     ///< CDT deceleration 5/7 mu_r g
std::vector<CheckResult> clump_free_rotation(const Options& o);  ///< energy and |L| of a torque-free clump
std::vector<CheckResult> rest(const Options& o);                 ///< at rest stays at rest for 1e5 steps
std::vector<CheckResult> mesh_contact(const Options& o);         ///< plane vs mesh face/edge/vertex; rolling over edges
std::vector<CheckResult> gate_turn(const Options& o);            ///< a scheduled 180-degree turn is exact
std::vector<CheckResult> servo_hold(const Options& o);           ///< a servo lid holds 10 kPa on a bed within 1%

/// Every check above, in that order.
std::vector<CheckResult> run_all(const Options& o);

}  // namespace bushel::verification
