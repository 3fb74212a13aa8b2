// The part stage: each geometry part's faces and broad phase once, its prescribed motion and
// servo every step.

#include <limits>

#include "stages.hpp"

namespace bushel::engine {

PartGeometry make_part_geometry(const Part& part) {
  PartGeometry g;
  g.faces = faces_of(part.shape);
  const bool plane = std::holds_alternative<PlaneSpec>(part.shape);
  g.lo = Vec3{INFINITY, INFINITY, INFINITY};
  g.hi = -1.0 * g.lo;
  for (const Face& f : g.faces) {
    Vec3 lo, hi;
    bounds(f, lo, hi);
    g.lo = min(g.lo, lo);
    g.hi = max(g.hi, hi);
  }
  const Vec3 far = max(-1.0 * g.lo, g.hi);
  g.reach = plane ? std::numeric_limits<double>::infinity() : norm(far);
  // A grid pays off once a sphere would otherwise test many faces.
  g.use_grid = g.faces.size() > 16;
  if (g.use_grid) g.grid = FaceGrid(g.faces);
  g.rotation = to_matrix(part.pose.orientation);
  return g;
}

void move_parts(std::span<Part> parts, std::span<PartGeometry> geometry, double skin, double t, double dt,
                PartCandidates& candidates) {
  for (std::size_t w = 0; w < parts.size(); ++w) {
    Part& part = parts[w];
    if (part.motion.empty()) continue;
    PartGeometry& g = geometry[w];
    g.moved += advance(part.motion, part.servo.speed, part.pose, t, dt, g.reach);
    g.rotation = to_matrix(part.pose.orientation);
    part.twist = twist_at(part.motion, part.servo.speed, part.pose, t + dt);
    // A face may now be up to `moved` closer to a sphere than at the last build.
    if (g.moved > 0.5 * skin) candidates.stale = true;
  }
}

void update_servos(std::span<Part> parts, double time) {
  for (Part& part : parts) {
    if (part.motion.has_servo)
      part.servo = update_servo(part.motion.servo, part.servo, part.force, part.pose.position, time);
  }
}

}  // namespace bushel::engine
