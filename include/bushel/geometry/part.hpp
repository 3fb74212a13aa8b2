#pragma once
// A geometry part: one primitive or mesh with a name, a material, a pose and a motion
// (docs/physics.md section 6). The name keys the contact pair table like a particle type. The
// simulation moves the part and fills in what the particles did to it each step.

#include <string>

#include "bushel/geometry/motion.hpp"
#include "bushel/geometry/shapes.hpp"
#include "bushel/particles/material.hpp"

namespace bushel {

struct Part {
  std::string name;  ///< keys the pair table, e.g. "cup"
  ShapeSpec shape;   ///< in the part frame
  Material material;
  Pose pose;            ///< part frame in the world at the current time
  Motion motion;        ///< prescribed segments and servo; empty = still
  bool enabled = true;  ///< a disabled part is not touched by particles (a gate taken away)

  // --- filled in by the simulation ---------------------------------------------------------
  Vec3 force;               ///< force the particles applied to the part in the last step [N]
  Vec3 torque;              ///< its torque about the part origin (pose.position) [N m]
  Twist twist;              ///< velocity of the origin [m/s] and angular velocity [rad/s] now
  ServoState servo;         ///< the servo's last action (when motion.has_servo)
  std::size_t touches = 0;  ///< sphere contacts in the last step
};

/// A part with the given shape at `pose`.
Part make_part(std::string name, ShapeSpec shape, Material material, Pose pose = {});
/// The infinite plane through `point` [m] whose unit `normal` points to where particles live.
Part plane_part(std::string name, Material material, const Vec3& point, const Vec3& normal);
/// A motion's own checks (Motion::validate) plus what the shape allows: an infinite plane
/// may translate but not rotate. Throws InputError keyed "motion...".
void validate_motion(const ShapeSpec& shape, const Motion& motion);
/// The orientation that turns the part frame's +z onto the unit vector `direction`.
Quat orientation_towards(const Vec3& direction);

}  // namespace bushel
