#pragma once
// How a geometry part moves (docs/physics.md section 6): prescribed segments, each active over
// [start, end), and an optional servo that moves the part along an axis to hold a force.
// Segments active at the same time add up. Displacements are integrated exactly over the
// part of each step a segment is active, so a gate told to turn 180 degrees at 7.85 rad/s
// turns exactly pi, whatever the time step.

#include <cstdint>
#include <limits>
#include <vector>

#include "bushel/core/quat.hpp"
#include "bushel/core/vec3.hpp"

namespace bushel {

/// Where a part's frame is in the world: x_world = position + orientation * x_part.
struct Pose {
  Vec3 position;     ///< origin of the part frame [m]
  Quat orientation;  ///< part frame -> world
};

struct MotionSegment {
  enum class Kind {
    translate,  ///< constant velocity
    rotate,     ///< constant angular speed about a fixed world axis through `point`
    oscillate,  ///< x = amplitude sin(2 pi frequency (t - start)) along `direction`
    tap,        ///< once per period: lifted by `amplitude` along `direction` (half-cosine), then
                ///< dropped in free fall at `gravity` onto its start position (a tapping device)
  };
  Kind kind = Kind::translate;
  /// Zero: the room between `kind` and `start`, named so that a checkpoint, which stores this
  /// struct's bytes, holds no uninitialised memory.
  std::uint32_t padding = 0;
  double start = 0.0;                                    ///< [s]
  double end = std::numeric_limits<double>::infinity();  ///< [s]
  Vec3 velocity;                                         ///< translate [m/s]
  Vec3 axis{0, 0, 1};                                    ///< rotate: unit axis (right-handed)
  Vec3 point;                                            ///< rotate: a point on the axis [m]
  double angular_speed = 0.0;                            ///< rotate [rad/s]
  Vec3 direction{0, 0, 1};                               ///< oscillate, tap: unit direction
  double amplitude = 0.0;                                ///< oscillate, tap [m]
  double frequency = 0.0;                                ///< oscillate, tap [Hz]
  double gravity = 9.81;                                 ///< tap: free-fall acceleration [m/s2]

  /// A rotation by `angle` [rad] at `angular_speed` [rad/s] starting at `start` [s].
  static MotionSegment turn(const Vec3& axis, const Vec3& point, double angle, double angular_speed, double start);
  /// Displacement along `direction` at time t (oscillate, tap) [m].
  double offset(double t) const;
  /// Its rate [m/s].
  double offset_rate(double t) const;
};
static_assert(sizeof(MotionSegment) == 19 * sizeof(double), "MotionSegment has no unnamed padding");

/// Moves a part along `axis` to hold the force the particles exert against that motion at
/// `target_force`: speed = gain (target - measured), limited to max_speed, and never past
/// `limit` (a striker pressed onto a rim with a hand's force, which rides up over a kernel
/// caught under it instead of crushing it).
struct ServoSpec {
  Vec3 axis{0, 0, -1};        ///< unit direction of travel that loads the particles
  double target_force = 0.0;  ///< [N]
  double area = 0.0;          ///< loaded area, for pressures (target = pressure x area) [m2]; 0 = none
  double gain = 0.0;          ///< [m/(s N)]
  double max_speed = 0.0;     ///< [m/s]
  double tolerance = 0.01;    ///< held while |measured - target| <= tolerance x target [-]
  double start = 0.0;         ///< [s]
  double end = std::numeric_limits<double>::infinity();  ///< [s]
  /// The part's origin goes along the axis no further than dot(origin, axis) = limit [m]
  double limit = std::numeric_limits<double>::infinity();
};

/// What a servo did in the last step.
struct ServoState {
  double measured_force = 0.0;  ///< force against the axis [N]
  double speed = 0.0;           ///< along the axis [m/s]
  bool held = false;            ///< within tolerance now
  /// Zero: the room after `held`, named so that a checkpoint, which stores this struct's
  /// bytes, holds no uninitialised memory.
  std::uint8_t padding[7] = {};
  double held_since = -1.0;  ///< time the current hold began [s]; -1 when not held
};
static_assert(sizeof(ServoState) == 4 * sizeof(double), "ServoState has no unnamed padding");

struct Motion {
  std::vector<MotionSegment> segments;
  bool has_servo = false;
  ServoSpec servo;

  bool empty() const { return segments.empty() && !has_servo; }
  /// Throws InputError (key "motion...") for unit vectors that are not, negative times,
  /// non-positive frequencies or speeds, ...
  void validate() const;
};

/// Velocity of the part origin [m/s] and angular velocity [rad/s] at time t.
struct Twist {
  Vec3 velocity;
  Vec3 angular_velocity;
};

/// Advances `pose` from t to t + dt; `servo_speed` is the servo's current speed along its
/// axis. Returns a bound on how far any point within `reach` of the origin moved [m].
double advance(const Motion& motion, double servo_speed, Pose& pose, double t, double dt, double reach);
/// The part's twist at time t.
Twist twist_at(const Motion& motion, double servo_speed, const Pose& pose, double t);
/// The servo's new state from the force the particles applied to the part at time t, with
/// the part's origin at `position` [m].
ServoState update_servo(const ServoSpec& servo, const ServoState& previous, const Vec3& force_on_part,
                        const Vec3& position, double t);

}  // namespace bushel
