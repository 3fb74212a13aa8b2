// parts: their shapes, poses and motions (motions are read for stages too).

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <utility>

#include "bushel/io/stl.hpp"
#include "scenario_reading.hpp"

namespace bushel::scenario_reading {
namespace {

namespace dim = units::dim;

Side read_side(const ScenarioNode& n) {
  if (!n.has("side")) return Side::both;
  const std::string s = n.at("side").choice({"inside", "outside", "both"});
  return s == "inside" ? inside : (s == "outside" ? outside : Side::both);
}

// mesh: an STL file, relative to the scenario's folder
MeshSpec read_mesh(const ScenarioNode& n, const std::string& scenario_dir) {
  const ScenarioNode file = n.at("file");
  std::filesystem::path path = file.text();
  if (path.is_relative()) path = std::filesystem::path(scenario_dir) / path;
  double scale = 1.0;
  if (const auto unit = n.find("unit")) {
    try {
      scale = units::parse("1 " + unit->text(), dim::length);
    } catch (const InputError&) {
      throw unit->error("expected the unit of the file's coordinates: a unit of length (m, cm, mm), got '" +
                        unit->text() + "'");
    }
  }
  try {
    return MeshSpec{io::read_stl(path.string(), scale), path.string()};
  } catch (const InputError& e) {
    throw file.error(e.what());
  }
}

// A servo: it moves the part along its axis to hold a force (or a pressure over an area).
ServoSpec read_servo(const ScenarioNode& k, double start, double end) {
  k.allow_only({"axis", "force", "pressure", "area", "gain", "max_speed", "tolerance", "stop"});
  ServoSpec s;
  s.axis = k.has("axis") ? unit_vector(k.at("axis")) : Vec3{0, 0, -1};
  s.area = k.positive_or("area", dim::area, 0.0);
  if (k.one_of({"force", "pressure"}) == "force") {
    s.target_force = k.positive("force", dim::force);
  } else {
    if (s.area == 0.0) throw k.error("a target pressure needs the loaded 'area'");
    s.target_force = k.positive("pressure", dim::pressure) * s.area;
  }
  // gain in (m/s)/N: a speed per force; given as the speed at the full target error
  s.max_speed = k.positive("max_speed", dim::velocity);
  s.gain = k.has("gain") ? k.at("gain").number() : s.max_speed / s.target_force;
  if (!(s.gain > 0.0)) throw k.at("gain").error("expected a positive gain in (m/s)/N");
  s.tolerance = k.has("tolerance") ? k.at("tolerance").quantity(dim::dimensionless) : 0.01;
  if (!(s.tolerance > 0.0 && s.tolerance < 1.0)) throw k.at("tolerance").error("expected a tolerance in (0, 100%)");
  // a point that the part's origin does not pass along the axis
  if (k.has("stop")) s.limit = dot(k.at("stop").vector(dim::length), s.axis);
  s.start = start;
  s.end = end;
  return s;
}

// A translate, rotate, oscillate or tap segment `k` of the list item `seg`.
MotionSegment read_segment(const ScenarioNode& seg, const ScenarioNode& k, const std::string& kind, double start,
                           double end) {
  MotionSegment s;
  if (kind == "translate") {
    s.kind = MotionSegment::Kind::translate;
    s.velocity = k.vector(dim::velocity);
  } else if (kind == "rotate") {
    k.allow_only({"axis", "point", "speed", "angle"});
    const Vec3 axis = unit_vector(k.at("axis"));
    const Vec3 point = k.vector_or("point", dim::length, {});
    const double speed = k.positive("speed", dim::angular_velocity);
    if (k.has("angle")) {
      s = MotionSegment::turn(axis, point, k.positive("angle", dim::angle), speed, start);
      if (seg.has("end")) throw seg.at("end").error("a rotation by an angle ends by itself; give either angle or end");
    } else {
      s.kind = MotionSegment::Kind::rotate;
      s.axis = axis;
      s.point = point;
      s.angular_speed = speed;
    }
  } else {
    k.allow_only({"direction", "amplitude", "frequency", "gravity"});
    s.kind = kind == "tap" ? MotionSegment::Kind::tap : MotionSegment::Kind::oscillate;
    s.direction = k.has("direction") ? unit_vector(k.at("direction")) : Vec3{0, 0, 1};
    s.amplitude = k.positive("amplitude", dim::length);
    s.frequency = k.positive("frequency", dim::frequency);
    s.gravity = k.positive_or("gravity", dim::acceleration, 9.81);
  }
  if (kind != "rotate" || !k.has("angle")) {
    s.start = start;
    s.end = end;
  }
  return s;
}

// The simulation's own checks of a part (what its shape allows of its motion, its pose,
// faces), before any step: the run would meet them in add_part.
void check_part(const ScenarioNode& n, const Part& part, SimulationSettings settings) {
  settings.dt = 1.0;  // (not read yet; no check of a part depends on it)
  try {
    Simulation(std::move(settings)).add_part(part);
  } catch (const InputError& e) {
    throw n.error(e.problem());
  }
}

// Bounds of a part's faces in the world [m].
std::pair<Vec3, Vec3> part_bounds(const Part& part) {
  const TriangleMesh mesh = tessellate(faces_of(part.shape), 32, 0.0);
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Vec3& v : mesh.vertices) {
    const Vec3 w = part.pose.position + rotate(part.pose.orientation, v);
    lo = min(lo, w);
    hi = max(hi, w);
  }
  return {lo, hi};
}

// The keys a part of this shape may have.
std::vector<std::string_view> part_keys(const std::string& shape) {
  std::vector<std::string_view> keys = {"shape", "material", "position", "motion", "enabled"};
  static const std::map<std::string, std::vector<std::string_view>> shape_keys = {
      {"plane", {"normal"}},
      {"disc", {"radius", "inner_radius", "axis", "angle"}},
      {"cylinder", {"radius", "height", "side", "cap_bottom", "cap_top", "axis", "angle"}},
      {"cone", {"bottom_radius", "top_radius", "height", "side", "cap_bottom", "cap_top", "axis", "angle"}},
      {"funnel", {"top_diameter", "outlet_diameter", "wall_angle", "axis", "angle"}},
      {"box", {"size", "side", "axis", "angle"}},
      {"plate", {"length", "width", "axis", "angle"}},
      {"mesh", {"file", "unit", "axis", "angle"}}};
  const auto& extra = shape_keys.at(shape);
  keys.insert(keys.end(), extra.begin(), extra.end());
  return keys;
}

Part read_part(const std::string& name, const ScenarioNode& p, const Scenario& sc, const ReadContext& cx) {
  const std::string shape =
      p.at("shape").choice({"plane", "disc", "cylinder", "cone", "funnel", "box", "plate", "mesh"});
  p.allow_only(part_keys(shape), "a " + shape);
  const Material& mat = cx.materials.at(cx.material_names[index_in(p.at("material"), cx.material_names, "material")]);
  Pose pose{p.vector_or("position", dim::length, {}), Quat::identity()};
  if (shape == "plane") {
    pose.orientation = orientation_towards(p.has("normal") ? unit_vector(p.at("normal")) : Vec3{0, 0, 1});
  } else if (p.has("angle")) {
    pose.orientation = Quat::from_axis_angle(unit_vector(p.at("axis")), p.at("angle").quantity(dim::angle));
  }
  Part part = make_part(name, read_shape(p, shape, cx.dir), mat, pose);
  if (const auto m = p.find("motion")) part.motion = read_motion(*m);
  part.enabled = p.boolean_or("enabled", true);
  check_part(p, part, sc.settings);
  if (shape != "plane") {
    const auto [lo, hi] = part_bounds(part);
    require_inside(p, lo, hi, sc.domain, "the part");
  }
  return part;
}

}  // namespace

ShapeSpec read_shape(const ScenarioNode& n, const std::string& shape, const std::string& scenario_dir) {
  if (shape == "plane") return PlaneSpec{};
  if (shape == "disc")
    return DiscSpec{n.positive("radius", dim::length), n.non_negative_or("inner_radius", dim::length, 0.0)};
  if (shape == "cylinder") {
    return CylinderSpec{n.positive("radius", dim::length), n.positive("height", dim::length), read_side(n),
                        n.boolean_or("cap_bottom", false), n.boolean_or("cap_top", false)};
  }
  if (shape == "cone") {
    return ConeSpec{n.non_negative_or("bottom_radius", dim::length, 0.0),
                    n.non_negative_or("top_radius", dim::length, 0.0),
                    n.positive("height", dim::length),
                    read_side(n),
                    n.boolean_or("cap_bottom", false),
                    n.boolean_or("cap_top", false)};
  }
  if (shape == "funnel") {
    const double angle = n.quantity("wall_angle", dim::angle);
    if (!(angle > 0.0 && angle < 0.5 * std::numbers::pi))
      throw n.at("wall_angle").error("expected an angle between 0 and 90 deg");
    try {
      return ConeSpec::funnel(n.positive("top_diameter", dim::length), n.positive("outlet_diameter", dim::length),
                              angle);
    } catch (const InputError& e) {  // (the shape's own check names the key)
      throw n.at(e.key().empty() ? std::string("outlet_diameter") : e.key()).error(e.problem());
    }
  }
  if (shape == "box") {
    const Vec3 size = n.at("size").vector(dim::length);
    if (!(size.x > 0.0 && size.y > 0.0 && size.z > 0.0)) throw n.at("size").error("expected positive edge lengths");
    return BoxSpec{size, read_side(n)};
  }
  if (shape == "plate") return PlateSpec{n.positive("length", dim::length), n.positive("width", dim::length)};
  return read_mesh(n, scenario_dir);
}

Motion read_motion(const ScenarioNode& list) {
  Motion m;
  for (const ScenarioNode& seg : list.items()) {
    seg.allow_only({"translate", "rotate", "oscillate", "tap", "servo", "start", "end"});
    const std::string kind = seg.one_of({"translate", "rotate", "oscillate", "tap", "servo"});
    const double start = seg.non_negative_or("start", dim::time, 0.0);
    const double end = seg.has("end") ? seg.positive("end", dim::time) : std::numeric_limits<double>::infinity();
    if (!(end > start)) throw seg.at("end").error("expected an end after the start");
    const ScenarioNode k = seg.at(kind);
    if (kind == "servo") {
      const ServoSpec s = read_servo(k, start, end);
      if (m.has_servo) throw seg.error("a part has at most one servo");
      m.has_servo = true;
      m.servo = s;
      continue;
    }
    m.segments.push_back(read_segment(seg, k, kind, start, end));
  }
  try {
    m.validate();
  } catch (const InputError& e) {
    throw list.error(e.problem());
  }
  return m;
}

void read_parts(const ScenarioNode& parts, Scenario& sc, ReadContext& cx) {
  for (const auto& [name, p] : parts.entries()) {
    sc.parts.push_back(read_part(name, p, sc, cx));
    cx.part_names.push_back(name);
  }
}

}  // namespace bushel::scenario_reading
