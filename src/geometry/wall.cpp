#include "bushel/geometry/wall.hpp"

#include <algorithm>
#include <cmath>

namespace bushel {

WallTouch touch(const PlaneShape& s, const Vec3& p, double r) {
  const double d = dot(p - s.point, s.normal);
  if (d >= r) return {};
  return {true, -s.normal, r - d, p - d * s.normal};
}

WallTouch touch(const CylinderShape& s, const Vec3& p, double r) {
  if (p.z < s.z_min || p.z > s.z_max) return {};
  const Vec3 radial{p.x - s.axis_point.x, p.y - s.axis_point.y, 0.0};
  const double rho = norm(radial);
  const double gap = s.radius - rho;
  if (gap >= r || rho == 0.0) return {};
  const Vec3 n = radial / rho;
  return {true, n, r - gap, Vec3{s.axis_point.x, s.axis_point.y, p.z} + s.radius * n};
}

double clearance(const PlaneShape& s, const Vec3& p, double r) { return dot(p - s.point, s.normal) - r; }

double clearance(const CylinderShape& s, const Vec3& p, double r) {
  const double rho = std::hypot(p.x - s.axis_point.x, p.y - s.axis_point.y);
  // Outside the wall's height band the centre must first move back into it (touch() tests
  // the centre's height).
  return std::max({s.radius - rho - r, s.z_min - p.z, p.z - s.z_max});
}

}  // namespace bushel
