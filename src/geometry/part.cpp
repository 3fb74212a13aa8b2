#include "bushel/geometry/part.hpp"

#include "bushel/core/input_error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace bushel {

Part make_part(std::string name, ShapeSpec shape, Material material, Pose pose) {
  Part p;
  p.name = std::move(name);
  p.shape = std::move(shape);
  p.material = std::move(material);
  p.pose = pose;
  return p;
}

Part plane_part(std::string name, Material material, const Vec3& point, const Vec3& normal) {
  return make_part(std::move(name), PlaneSpec{}, std::move(material), {point, orientation_towards(normal)});
}

// Every point of a turning infinite plane would move without bound.
void validate_motion(const ShapeSpec& shape, const Motion& motion) {
  motion.validate();
  if (std::holds_alternative<PlaneSpec>(shape) &&
      std::any_of(motion.segments.begin(), motion.segments.end(),
                  [](const MotionSegment& m) { return m.kind == MotionSegment::Kind::rotate; })) {
    throw InputError("an infinite plane cannot rotate; use a plate or a disc").with_key("motion");
  }
}

Quat orientation_towards(const Vec3& direction) {
  if (!(norm(direction) > 0.0) || !std::isfinite(norm(direction))) {
    throw InputError("expected a non-zero finite direction").with_key("normal");
  }
  const Vec3 z{0, 0, 1}, d = normalized(direction);
  const Vec3 axis = cross(z, d);
  const double s = norm(axis), c = dot(z, d);
  if (s < 1e-12) return c > 0.0 ? Quat::identity() : Quat::from_axis_angle({1, 0, 0}, std::numbers::pi);
  return Quat::from_axis_angle(axis / s, std::atan2(s, c));
}

}  // namespace bushel
