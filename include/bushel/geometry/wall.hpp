#pragma once
// Walls of the engine core: an infinite plane and the inside of a finite vertical cylinder
// (enough for verification and a poured bed; the geometry issue adds meshes and motion).
// A wall has a material and a name, which key the contact pair table like a particle type.

#include <string>
#include <variant>

#include "bushel/core/vec3.hpp"
#include "bushel/particles/material.hpp"

namespace bushel {

/// Infinite plane through `point` whose unit `normal` points to the side particles live on.
struct PlaneShape {
  Vec3 point;            ///< [m]
  Vec3 normal{0, 0, 1};  ///< unit vector
};

/// Inner surface of a cylinder with a vertical axis: particles live inside.
struct CylinderShape {
  Vec3 axis_point;       ///< a point on the axis; only x, y matter [m]
  double radius = 0.0;   ///< inner radius [m]
  double z_min = -1e30;  ///< lower end of the wall [m]
  double z_max = 1e30;   ///< upper end of the wall [m]
};

/// Where a sphere touches a wall.
struct WallTouch {
  bool touching = false;
  Vec3 normal;           ///< unit vector from the sphere's centre towards the wall
  double overlap = 0.0;  ///< [m]
  Vec3 point;            ///< contact point [m]
};

struct Wall {
  std::string name;  ///< keys the pair table, e.g. "bottom"
  std::variant<PlaneShape, CylinderShape> shape;
  Material material;
  Vec3 force;   ///< force particles applied to the wall in the last step [N]
  Vec3 torque;  ///< torque of that force about the origin [N m]
};

/// Contact of a sphere (centre `p`, radius `r`) with a wall shape.
WallTouch touch(const PlaneShape& s, const Vec3& p, double r);
WallTouch touch(const CylinderShape& s, const Vec3& p, double r);
inline WallTouch touch(const Wall& w, const Vec3& p, double r) {
  return std::visit([&](const auto& s) { return touch(s, p, r); }, w.shape);
}

/// A lower bound on how far a sphere (centre `p`, radius `r`) must move before it can touch
/// the shape [m]; zero or negative while it may touch. The broad phase keeps a sphere-wall
/// pair while this is below the skin.
double clearance(const PlaneShape& s, const Vec3& p, double r);
double clearance(const CylinderShape& s, const Vec3& p, double r);
inline double clearance(const Wall& w, const Vec3& p, double r) {
  return std::visit([&](const auto& s) { return clearance(s, p, r); }, w.shape);
}

}  // namespace bushel
