#include "bushel/geometry/motion.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "bushel/core/input_error.hpp"

namespace bushel {
namespace {

constexpr double pi = std::numbers::pi;

bool active(double start, double end, double t) { return t >= start && t < end; }

// Tap: rise over the part of the period left after the free fall.
double fall_time(const MotionSegment& s) { return std::sqrt(2.0 * s.amplitude / s.gravity); }

void require_unit(const Vec3& v, const std::string& key) {
  if (!(std::abs(norm(v) - 1.0) < 1e-6)) throw InputError("expected a unit vector").with_key(key);
}
void require_positive(double v, const std::string& key, const char* unit) {
  if (!(v > 0.0 && std::isfinite(v))) {
    throw InputError(std::string("expected a positive finite value in ") + unit + ", got " + std::to_string(v))
        .with_key(key);
  }
}

}  // namespace

MotionSegment MotionSegment::turn(const Vec3& axis, const Vec3& point, double angle, double angular_speed,
                                  double start) {
  MotionSegment s;
  s.kind = Kind::rotate;
  s.axis = axis;
  s.point = point;
  s.angular_speed = std::copysign(std::abs(angular_speed), angle);
  s.start = start;
  s.end = start + std::abs(angle / angular_speed);
  return s;
}

double MotionSegment::offset(double t) const {
  const double tau = t - start;
  if (kind == Kind::oscillate) return amplitude * std::sin(2.0 * pi * frequency * tau);
  if (kind != Kind::tap) return 0.0;
  const double period = 1.0 / frequency, rise = period - fall_time(*this);
  const double phase = tau - period * std::floor(tau / period);
  if (phase < rise) return 0.5 * amplitude * (1.0 - std::cos(pi * phase / rise));
  const double s = phase - rise;
  return amplitude - 0.5 * gravity * s * s;
}

double MotionSegment::offset_rate(double t) const {
  const double tau = t - start;
  if (kind == Kind::oscillate) return amplitude * 2.0 * pi * frequency * std::cos(2.0 * pi * frequency * tau);
  if (kind != Kind::tap) return 0.0;
  const double period = 1.0 / frequency, rise = period - fall_time(*this);
  const double phase = tau - period * std::floor(tau / period);
  if (phase < rise) return 0.5 * amplitude * pi / rise * std::sin(pi * phase / rise);
  return -gravity * (phase - rise);
}

void Motion::validate() const {
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const MotionSegment& s = segments[i];
    const std::string key = "motion[" + std::to_string(i) + "]";
    if (!(s.start >= 0.0) || !(s.end > s.start)) {
      throw InputError("expected 0 <= start < end in seconds").with_key(key + ".start");
    }
    switch (s.kind) {
      case MotionSegment::Kind::translate:
        if (!std::isfinite(norm(s.velocity))) throw InputError("expected a finite velocity in m/s").with_key(key);
        break;
      case MotionSegment::Kind::rotate:
        require_unit(s.axis, key + ".axis");
        if (!std::isfinite(s.angular_speed)) throw InputError("expected a finite angular speed in rad/s").with_key(key);
        if (!std::isfinite(norm(s.point))) throw InputError("expected a finite point in m").with_key(key + ".point");
        break;
      case MotionSegment::Kind::tap:
        require_positive(s.gravity, key + ".gravity", "m/s2");
        [[fallthrough]];
      case MotionSegment::Kind::oscillate:
        require_unit(s.direction, key + ".direction");
        require_positive(s.amplitude, key + ".amplitude", "m");
        require_positive(s.frequency, key + ".frequency", "Hz");
        if (s.kind == MotionSegment::Kind::tap && !(fall_time(s) < 1.0 / s.frequency)) {
          throw InputError("the free fall over the amplitude takes longer than one tapping period")
              .with_key(key + ".frequency");
        }
        break;
    }
  }
  if (has_servo) {
    require_unit(servo.axis, "servo.axis");
    require_positive(servo.target_force, "servo.target_force", "N");
    require_positive(servo.gain, "servo.gain", "m/(s N)");
    require_positive(servo.max_speed, "servo.max_speed", "m/s");
    if (!(servo.tolerance > 0.0 && servo.tolerance < 1.0)) {
      throw InputError("expected a relative tolerance between 0 and 1").with_key("servo.tolerance");
    }
    if (!(servo.area >= 0.0 && std::isfinite(servo.area))) {
      throw InputError("expected a non-negative finite area in m2").with_key("servo.area");
    }
    if (!(servo.start >= 0.0) || !(servo.end > servo.start)) {
      throw InputError("expected 0 <= start < end in seconds").with_key("servo.start");
    }
    if (std::isnan(servo.limit)) throw InputError("expected a position along the axis in m").with_key("servo.limit");
  }
}

double advance(const Motion& motion, double servo_speed, Pose& pose, double t, double dt, double reach) {
  double moved = 0.0;
  const double t1 = t + dt;
  for (const MotionSegment& s : motion.segments) {
    const double lo = std::max(t, s.start), hi = std::min(t1, s.end);
    if (!(hi > lo)) continue;
    switch (s.kind) {
      case MotionSegment::Kind::translate:
        pose.position += (hi - lo) * s.velocity;
        moved += (hi - lo) * norm(s.velocity);
        break;
      case MotionSegment::Kind::oscillate:
      case MotionSegment::Kind::tap: {
        const double d = s.offset(hi) - s.offset(lo);
        pose.position += d * s.direction;
        moved += std::abs(d);
        break;
      }
      case MotionSegment::Kind::rotate: {
        // A point y of the part moves by at most |angle| |y - point|.
        const double angle = s.angular_speed * (hi - lo);
        if (angle == 0.0) break;  // (and no 0 x inf for an unbounded part)
        const Quat turn = Quat::from_axis_angle(s.axis, angle);
        moved += std::abs(angle) * (reach + norm(pose.position - s.point));
        pose.position = s.point + rotate(turn, pose.position - s.point);
        pose.orientation = normalized(turn * pose.orientation);
        break;
      }
    }
  }
  if (motion.has_servo) {
    const double lo = std::max(t, motion.servo.start), hi = std::min(t1, motion.servo.end);
    if (hi > lo) {
      const ServoSpec& servo = motion.servo;
      double along = servo_speed * (hi - lo);
      if (along > 0.0) along = std::min(along, std::max(0.0, servo.limit - dot(pose.position, servo.axis)));
      pose.position += along * servo.axis;
      moved += std::abs(along);
    }
  }
  return moved;
}

Twist twist_at(const Motion& motion, double servo_speed, const Pose& pose, double t) {
  Twist w;
  for (const MotionSegment& s : motion.segments) {
    if (!active(s.start, s.end, t)) continue;
    switch (s.kind) {
      case MotionSegment::Kind::translate:
        w.velocity += s.velocity;
        break;
      case MotionSegment::Kind::oscillate:
      case MotionSegment::Kind::tap:
        w.velocity += s.offset_rate(t) * s.direction;
        break;
      case MotionSegment::Kind::rotate: {
        const Vec3 omega = s.angular_speed * s.axis;
        w.angular_velocity += omega;
        w.velocity += cross(omega, pose.position - s.point);
        break;
      }
    }
  }
  if (motion.has_servo && active(motion.servo.start, motion.servo.end, t))
    w.velocity += servo_speed * motion.servo.axis;
  return w;
}

ServoState update_servo(const ServoSpec& servo, const ServoState& previous, const Vec3& force_on_part,
                        const Vec3& position, double t) {
  ServoState s;
  s.measured_force = -dot(force_on_part, servo.axis);
  if (!active(servo.start, servo.end, t)) return s;
  const double error = servo.target_force - s.measured_force;
  s.speed = std::clamp(servo.gain * error, -servo.max_speed, servo.max_speed);
  // at its limit (within a nanometre: advance stops it there) it waits for the force to lift it
  if (s.speed > 0.0 && dot(position, servo.axis) >= servo.limit - 1e-9) s.speed = 0.0;
  s.held = std::abs(error) <= servo.tolerance * servo.target_force;
  s.held_since = s.held ? (previous.held ? previous.held_since : t) : -1.0;
  return s;
}

}  // namespace bushel
