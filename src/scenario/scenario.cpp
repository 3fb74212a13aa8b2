#include "bushel/scenario/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "bushel/contact/time_scales.hpp"
#include "bushel/core/did_you_mean.hpp"
#include "bushel/io/stl.hpp"
#include "bushel/particles/template_library.hpp"
#include "bushel/scenario/scenario_node.hpp"

namespace bushel {
namespace {

namespace dim = units::dim;

// A name from a list of known names, with a did-you-mean; errors point at `node`.
std::size_t index_named(const ScenarioNode& node, const std::string& name, const std::vector<std::string>& names,
                        const std::string& what) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it != names.end()) return static_cast<std::size_t>(it - names.begin());
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  throw node.error("unknown " + what + " '" + name + "'" + did_you_mean(name, names) + "; the scenario has " +
                   (known.empty() ? std::string("none") : known));
}

std::size_t index_in(const ScenarioNode& node, const std::vector<std::string>& names, const std::string& what) {
  return index_named(node, node.text(), names, what);
}

Vec3 unit_vector(const ScenarioNode& node) {
  const Vec3 v = node.vector(dim::dimensionless);
  const double n = norm(v);
  if (!(n > 0.0) || !std::isfinite(n)) throw node.error("expected a non-zero direction, e.g. '0 0 -1'");
  return v / n;
}

Region read_region(const ScenarioNode& n) {
  const std::string shape = n.at("shape").choice({"cylinder", "box"});
  if (shape == "cylinder") {
    n.allow_only({"shape", "base", "radius", "height"});
    return Region::cylinder(n.vector_or("base", dim::length, {}), n.positive("radius", dim::length),
                            n.positive("height", dim::length));
  }
  n.allow_only({"shape", "centre", "size"});
  const Vec3 size = n.at("size").vector(dim::length);
  if (!(size.x > 0.0 && size.y > 0.0 && size.z > 0.0)) throw n.at("size").error("expected positive edge lengths");
  return Region::box(n.vector_or("centre", dim::length, {}), size);
}

// A region must lie within the domain (a box).
void require_inside(const ScenarioNode& n, const Vec3& lo, const Vec3& hi, const Region& domain,
                    const std::string& what) {
  const Vec3 dl = domain.lo(), dh = domain.hi();
  const double eps = 1e-9;
  if (lo.x < dl.x - eps || lo.y < dl.y - eps || lo.z < dl.z - eps || hi.x > dh.x + eps || hi.y > dh.y + eps ||
      hi.z > dh.z + eps) {
    throw n.error(
        fmt::format("{} reaches from ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g}) m, outside the "
                    "domain ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g}) m (simulation.domain)",
                    what, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, dl.x, dl.y, dl.z, dh.x, dh.y, dh.z));
  }
}

Side read_side(const ScenarioNode& n) {
  if (!n.has("side")) return Side::both;
  const std::string s = n.at("side").choice({"inside", "outside", "both"});
  return s == "inside" ? inside : (s == "outside" ? outside : Side::both);
}

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
  // mesh: an STL file, relative to the scenario's folder
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

// Motion segments, times from the start of the run (of the stage, for a stage's motions).
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
      if (m.has_servo) throw seg.error("a part has at most one servo");
      m.has_servo = true;
      m.servo = s;
      continue;
    }
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
        if (seg.has("end"))
          throw seg.at("end").error("a rotation by an angle ends by itself; give either angle or end");
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
    m.segments.push_back(s);
  }
  try {
    m.validate();
  } catch (const InputError& e) {
    throw list.error(e.problem());
  }
  return m;
}

ContactParameters read_contact(const ScenarioNode& n, const ContactParameters& base) {
  ContactParameters p = base;
  if (n.has("restitution")) p.restitution = n.at("restitution").quantity(dim::dimensionless);
  if (n.has("static_friction")) p.static_friction = n.at("static_friction").quantity(dim::dimensionless);
  if (n.has("rolling_friction")) p.rolling_friction = n.at("rolling_friction").quantity(dim::dimensionless);
  try {
    validate(p);
  } catch (const InputError& e) {
    throw n.at(e.key().empty() ? std::string("restitution") : e.key()).error(e.problem());
  }
  return p;
}

// The simulation's own checks of a part (what its shape allows of its motion, its pose,
// faces), before any step: the run would meet them in add_part.
void check_part(const ScenarioNode& n, const Part& part, const SimulationSettings& settings) {
  try {
    Simulation(settings).add_part(part);
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

// `parent`'s time_step, "20 us" or "0.2 rayleigh" (of the smallest element's Rayleigh step):
// [s]. `fraction` is set to the Rayleigh fraction if given so, else 0.
// The strongest gravity a scenario may set [m/s2]: 100 times the Earth's, far beyond any
// centrifuge test of grain; more is a typo (a unit or an exponent).
constexpr double max_gravity = 1000.0;

// simulation: guards: each limit a fraction or quantity in its range (run_guards.hpp).
RunGuards read_guards(const ScenarioNode& g) {
  g.allow_only({"max_overlap", "overlap_time", "max_speed", "max_travel", "max_lost", "max_steps"});
  RunGuards r;
  auto fraction = [&](const char* key, double fallback, double hi) {
    if (!g.has(key)) return fallback;
    const double v = g.at(key).quantity(dim::dimensionless);
    if (!(v > 0.0 && v <= hi)) throw g.at(key).error(fmt::format("expected a fraction in (0, {:g}], e.g. 50%", hi));
    return v;
  };
  r.max_overlap = fraction("max_overlap", r.max_overlap, 1.0);
  r.max_travel = fraction("max_travel", r.max_travel, 1.0);
  r.max_lost = fraction("max_lost", r.max_lost, 1.0);
  r.overlap_time = g.positive_or("overlap_time", dim::time, r.overlap_time);
  r.max_speed = g.positive_or("max_speed", dim::velocity, r.max_speed);
  if (g.has("max_steps")) r.max_steps = static_cast<double>(g.at("max_steps").integer(1, 1L << 50));
  return r;
}

// The stages' time limits against their time steps: a step far too short for the run (a
// template sphere of 1e-300 mm) would make a run that never ends.
void check_step_count(const Scenario& sc, const ScenarioNode& stages) {
  double steps = 0.0;
  for (const StageSpec& s : sc.stages) {
    if (!s.enabled) continue;
    const double limit = s.duration ? std::min(*s.duration, s.max_time) : s.max_time;
    steps += limit / s.dt.value_or(sc.settings.dt);
  }
  if (!(steps <= sc.guards.max_steps)) {
    throw stages.error(fmt::format(
        "the stages' time limits need up to {:.3g} steps of {:.3g} s, more than the guard's {:.3g} "
        "(simulation.guards.max_steps): a time step far too short for the run (a particle far too small?) or "
        "a time limit far too long",
        steps, sc.settings.dt, sc.guards.max_steps));
  }
}

double read_time_step(const ScenarioNode& parent, double rayleigh_step, double& fraction) {
  const ScenarioNode ts = parent.at("time_step");
  const std::string text = ts.text();
  const std::string suffix = "rayleigh";
  if (text.size() > suffix.size() && text.ends_with(suffix)) {
    try {
      fraction = units::parse(text.substr(0, text.size() - suffix.size()), dim::dimensionless);
    } catch (const InputError& e) {
      throw ts.error(e.problem());
    }
    if (!(fraction > 0.0 && fraction <= 1.0)) {
      throw ts.error("expected a fraction of the Rayleigh step in (0, 1], e.g. '0.2 rayleigh' or '20% rayleigh'");
    }
    return fraction * rayleigh_step;
  }
  fraction = 0.0;
  double dt = 0.0;
  try {
    dt = parent.positive("time_step", dim::time);
  } catch (const InputError& e) {  // (say the other form too: "0.2 rayleighs" is a typo of it)
    throw ts.error(e.problem() + "; or a fraction of the smallest element's Rayleigh step, e.g. '0.2 rayleigh'");
  }
  if (dt > rayleigh_step) {
    throw ts.error(fmt::format(
        "a time step of {:.4g} us is above the Rayleigh step of the smallest element ({:.4g} us): the contacts "
        "would be unstable",
        dt * 1e6, rayleigh_step * 1e6));
  }
  return dt;
}

}  // namespace

std::vector<std::string> SensorSpec::values(const std::vector<std::string>& type_names) const {
  switch (kind) {
    case Kind::region: {
      std::vector<std::string> v = {"mass",         "count",  "bulk_density",  "bulk_density_exact", "packing_fraction",
                                    "coordination", "volume", "surface_margin"};
      for (const auto& t : type_names) v.push_back("fraction_" + t);
      return v;
    }
    case Kind::part: {
      std::vector<std::string> v = {"force"};
      if (area > 0.0) v.push_back("pressure");
      v.insert(v.end(), {"force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z", "position_z", "angle"});
      return v;
    }
    case Kind::heap:
      return {"height", "angle"};
    case Kind::flow:
      return {"mass", "rate"};
  }
  return {};
}

const std::vector<std::string>& global_value_names() {
  static const std::vector<std::string> names = {"time",
                                                 "particles",
                                                 "kinetic_energy",
                                                 "kinetic_energy_per_particle",
                                                 "potential_energy",
                                                 "max_overlap_ratio",
                                                 "unbalanced_force",
                                                 "contacts",
                                                 "created_mass",
                                                 "removed_mass",
                                                 "lost_mass",
                                                 "lost_count"};
  return names;
}

units::Dimension value_dimension(const std::string& value_name) {
  namespace dim = units::dim;
  const std::string v = value_name.substr(value_name.rfind('.') + 1);
  static const std::map<std::string, units::Dimension> by_name = {{"time", dim::time},
                                                                  {"kinetic_energy", dim::energy},
                                                                  {"kinetic_energy_per_particle", dim::energy},
                                                                  {"potential_energy", dim::energy},
                                                                  {"created_mass", dim::mass},
                                                                  {"removed_mass", dim::mass},
                                                                  {"lost_mass", dim::mass},
                                                                  {"mass", dim::mass},
                                                                  {"bulk_density", dim::density},
                                                                  {"bulk_density_exact", dim::density},
                                                                  {"volume", dim::volume},
                                                                  {"force", dim::force},
                                                                  {"force_x", dim::force},
                                                                  {"force_y", dim::force},
                                                                  {"force_z", dim::force},
                                                                  {"pressure", dim::pressure},
                                                                  {"torque_x", dim::energy},  // N m
                                                                  {"torque_y", dim::energy},
                                                                  {"torque_z", dim::energy},
                                                                  {"position_z", dim::length},
                                                                  {"surface_margin", dim::length},
                                                                  {"height", dim::length},
                                                                  {"rate", dim::mass_flow},
                                                                  {"start", dim::time},
                                                                  {"end", dim::time},
                                                                  {"duration", dim::time},
                                                                  {"angle", dim::angle}};
  const auto it = by_name.find(v);
  return it == by_name.end() ? dim::dimensionless : it->second;  // counts, fractions, ratios
}

namespace {
constexpr double degree = std::numbers::pi / 180.0;
}

double value_to_si(const std::string& value_name, double value) {
  return value_dimension(value_name) == units::dim::angle ? value * degree : value;
}

double value_from_si(const std::string& value_name, double value_si) {
  return value_dimension(value_name) == units::dim::angle ? value_si / degree : value_si;
}

std::string_view result_unit(units::Dimension d) { return d == units::dim::angle ? "deg" : units::si_symbol(d); }

double result_value(const units::Quantity& q) { return q.dimension == units::dim::angle ? q.value / degree : q.value; }

units::Quantity evaluate_result(const ResultSpec& result,
                                const std::function<double(const std::string&, const std::string&)>& value) {
  return units::evaluate(result.expression, [&](const std::string& name) {
    const std::size_t dot = name.find('.');
    if (dot == std::string::npos) {
      throw InputError("'" + name + "' is not a stage's value (expected stage.value, e.g. fill.cup.bulk_density)");
    }
    return units::Quantity{value_to_si(name, value(name.substr(0, dot), name.substr(dot + 1))), value_dimension(name)};
  });
}

std::vector<std::string> Scenario::value_names() const {
  std::vector<std::string> names = global_value_names();
  std::vector<std::string> type_names;
  for (const auto& t : types) type_names.push_back(t.name);
  for (const auto& s : sensors) {
    for (const auto& v : s.values(type_names)) names.push_back(s.name + "." + v);
  }
  return names;
}

Scenario read_scenario(ScenarioDocument document) {
  Scenario sc;
  const ScenarioNode root(document.root, "", document.file, &document.set_by);
  const std::string dir = std::filesystem::path(document.file).parent_path().string();
  root.allow_only({"parameters", "simulation", "materials", "particle_types", "contacts", "parts", "factories", "sinks",
                   "sensors", "stages", "results", "outputs"});

  // --- simulation ---------------------------------------------------------------------------
  const ScenarioNode sim = root.at("simulation");
  sim.allow_only({"time_step", "gravity", "integrator", "rolling", "skin", "domain", "seed", "threads",
                  "check_interval", "tangential_damping_limit", "guards"});
  SimulationSettings& st = sc.settings;
  st.gravity = sim.vector_or("gravity", dim::acceleration, {0, 0, -9.81});
  if (norm(st.gravity) > max_gravity) {
    throw sim.at("gravity").error(
        fmt::format("expected at most {:g} m/s2 (about 100 g), got {:.4g} m/s2", max_gravity, norm(st.gravity)));
  }
  if (sim.has("integrator")) {
    st.integrator = sim.at("integrator").choice({"symplectic_euler", "velocity_verlet"}) == "velocity_verlet"
                        ? Integrator::velocity_verlet
                        : Integrator::symplectic_euler;
  }
  if (sim.has("rolling")) st.rolling = sim.at("rolling").choice({"cdt", "epsd", "none"});
  st.skin = sim.positive_or("skin", dim::length, 0.0);
  if (const auto limit = sim.find("tangential_damping_limit")) {  // a fraction, or off
    if (limit->text() == "off") {
      st.tangential_damping_limit = std::numeric_limits<double>::infinity();
    } else {
      st.tangential_damping_limit = limit->number();
      if (!(st.tangential_damping_limit > 0.0 && st.tangential_damping_limit <= 1.0)) {
        throw limit->error("expected a fraction in (0, 1] of the relative tangential velocity per step, or off");
      }
    }
  }
  const std::uint64_t seed = sim.has("seed") ? static_cast<std::uint64_t>(sim.at("seed").integer(0, 1L << 40)) : 1;
  sc.threads = sim.has("threads") ? static_cast<int>(sim.at("threads").integer(0, 1024)) : 0;
  sc.check_interval = sim.positive_or("check_interval", dim::time, 1e-3);
  if (const auto g = sim.find("guards")) sc.guards = read_guards(*g);
  {
    const ScenarioNode d = sim.at("domain");
    d.allow_only({"min", "max"});
    const Vec3 lo = d.at("min").vector(dim::length), hi = d.at("max").vector(dim::length);
    if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) throw d.at("max").error("expected max above min on every axis");
    sc.domain = Region::box(0.5 * (lo + hi), hi - lo);
  }

  // --- materials and particle types ---------------------------------------------------------
  std::map<std::string, Material> materials;
  std::vector<std::string> material_names;
  for (const auto& [name, m] : root.at("materials").entries()) {
    m.allow_only({"shear_modulus", "poisson_ratio", "density"});
    Material mat{name, m.positive("shear_modulus", dim::pressure), m.at("poisson_ratio").number(),
                 m.positive("density", dim::density)};
    try {
      validate(mat);
    } catch (const InputError& e) {  // (its key is "NAME.field")
      const std::string field = e.key().substr(e.key().find('.') + 1);
      throw m.at(field.empty() || field == e.key() ? std::string("poisson_ratio") : field).error(e.problem());
    }
    materials[name] = mat;
    material_names.push_back(name);
  }
  if (materials.empty()) throw root.at("materials").error("expected at least one material");
  std::vector<std::string> type_names;
  for (const auto& [name, t] : root.at("particle_types").entries()) {
    t.allow_only({"template", "diameter", "material"});
    const Material& mat = materials.at(material_names[index_in(t.at("material"), material_names, "material")]);
    ParticleTemplate shape;
    if (t.one_of({"template", "diameter"}) == "diameter") {
      shape = make_template(name, {{{0, 0, 0}, 0.5 * t.positive("diameter", dim::length)}});
    } else {
      std::string spec = t.at("template").text();
      // A CSV file is found next to the scenario.
      if (spec.find(".csv") != std::string::npos && !std::filesystem::path(spec).is_absolute() && !dir.empty()) {
        spec = (std::filesystem::path(dir) / spec).string();
      }
      try {
        shape = resolve_template(spec);
      } catch (const InputError& e) {
        throw t.at("template").error(e.source().empty() ? e.problem() : e.what());  // (a CSV's file and line)
      }
    }
    sc.types.push_back({name, std::move(shape), mat});
    type_names.push_back(name);
  }
  if (sc.types.empty()) throw root.at("particle_types").error("expected at least one particle type");

  // --- time step ------------------------------------------------------------------------------
  sc.rayleigh_step = INFINITY;
  for (const auto& t : sc.types) {
    sc.rayleigh_step =
        std::min(sc.rayleigh_step, rayleigh_time_step(t.shape.min_sphere_radius(), t.material.density,
                                                      t.material.shear_modulus, t.material.poisson_ratio));
  }
  st.dt = read_time_step(sim, sc.rayleigh_step, sc.time_step_fraction);

  // --- contacts -------------------------------------------------------------------------------
  if (const auto c = root.find("contacts")) {
    c->allow_only({"default", "pairs"});
    ContactParameters defaults;
    if (const auto d = c->find("default")) {
      d->allow_only({"restitution", "static_friction", "rolling_friction"});
      defaults = read_contact(*d, defaults);
    }
    st.contacts = ContactTable(defaults);
    if (const auto pairs = c->find("pairs")) {
      for (const ScenarioNode& p : pairs->items()) {
        p.allow_only({"between", "restitution", "static_friction", "rolling_friction"});
        const auto two = p.at("between").items();
        if (two.size() != 2) throw p.at("between").error("expected two names: [a, b] (particle types or materials)");
        std::vector<std::string> names = type_names;
        names.insert(names.end(), material_names.begin(), material_names.end());
        const std::string a = names[index_in(two[0], names, "particle type or material")];
        const std::string b = names[index_in(two[1], names, "particle type or material")];
        st.contacts.set(a, b, read_contact(p, defaults));
      }
    }
  }

  // --- parts ----------------------------------------------------------------------------------
  std::vector<std::string> part_names;
  if (const auto parts = root.find("parts")) {
    for (const auto& [name, p] : parts->entries()) {
      const std::string shape =
          p.at("shape").choice({"plane", "disc", "cylinder", "cone", "funnel", "box", "plate", "mesh"});
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
      p.allow_only(keys, "a " + shape);
      const Material& mat = materials.at(material_names[index_in(p.at("material"), material_names, "material")]);
      Pose pose{p.vector_or("position", dim::length, {}), Quat::identity()};
      if (shape == "plane") {
        pose.orientation = orientation_towards(p.has("normal") ? unit_vector(p.at("normal")) : Vec3{0, 0, 1});
      } else if (p.has("angle")) {
        pose.orientation = Quat::from_axis_angle(unit_vector(p.at("axis")), p.at("angle").quantity(dim::angle));
      }
      Part part = make_part(name, read_shape(p, shape, dir), mat, pose);
      if (const auto m = p.find("motion")) part.motion = read_motion(*m);
      part.enabled = p.boolean_or("enabled", true);
      check_part(p, part, st);
      if (shape != "plane") {
        const auto [lo, hi] = part_bounds(part);
        require_inside(p, lo, hi, sc.domain, "the part");
      }
      sc.parts.push_back(std::move(part));
      part_names.push_back(name);
    }
  }

  // --- factories and sinks -------------------------------------------------------------------
  std::vector<std::string> factory_names, sink_names;
  if (const auto fs = root.find("factories")) {
    std::uint64_t k = 0;
    for (const auto& [name, f] : fs->entries()) {
      f.allow_only({"region", "surface", "rate", "mass", "count", "types", "fractions_by", "velocity", "start", "stop",
                    "enabled", "seed"});
      FactorySpec spec;
      spec.name = name;
      if (f.one_of({"region", "surface"}) == "region") {
        spec.region = read_region(f.at("region"));
        require_inside(f.at("region"), spec.region.lo(), spec.region.hi(), sc.domain, "the factory's region");
      } else {
        // a mesh (STL) on whose front side particles are created, moved to `position`
        const ScenarioNode surface = f.at("surface");
        surface.allow_only({"file", "unit", "position"});
        spec.surface = std::get<MeshSpec>(read_shape(surface, "mesh", dir)).mesh;
        const Vec3 shift = surface.vector_or("position", dim::length, {});
        Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
        for (Vec3& v : spec.surface.vertices) v = v + shift, lo = min(lo, v), hi = max(hi, v);
        require_inside(surface, lo, hi, sc.domain, "the factory's surface");
      }
      if (f.has("rate")) {
        const ScenarioNode r = f.at("rate");
        const bool per_second = r.text().ends_with("/s") && !r.text().ends_with("kg/s") && !r.text().ends_with("g/s");
        spec.rate_by_mass = !per_second;
        spec.rate = r.quantity(per_second ? dim::frequency : dim::mass_flow);
        if (!(spec.rate > 0.0)) throw r.error("expected a positive rate, e.g. '1 kg/s' or '500 /s'");
      }
      if (f.one_of({"mass", "count"}) == "mass") {
        spec.total = f.positive("mass", dim::mass);
      } else {
        spec.total_by_mass = false;
        spec.total = static_cast<double>(f.at("count").integer(1, 100'000'000));
      }
      spec.fractions_by_mass = !f.has("fractions_by") || f.at("fractions_by").choice({"mass", "count"}) == "mass";
      const ScenarioNode types = f.at("types");
      if (types.is_scalar()) {
        spec.types.push_back(static_cast<std::uint32_t>(index_in(types, type_names, "particle type")));
        spec.fractions.push_back(1.0);
      } else {
        double sum = 0.0;
        for (const auto& [tname, frac] : types.entries()) {
          spec.types.push_back(static_cast<std::uint32_t>(index_named(frac, tname, type_names, "particle type")));
          const double v = frac.quantity(dim::dimensionless);
          if (!(v >= 0.0)) throw frac.error("expected a share >= 0, e.g. 81.5%");
          spec.fractions.push_back(v);
          sum += v;
        }
        if (spec.types.empty()) throw types.error("expected at least one particle type");
        if (std::abs(sum - 1.0) > 1e-3)
          throw types.error(fmt::format("the shares add up to {:.4g}%, not 100%", 100 * sum));
        for (double& v : spec.fractions) v /= sum;
      }
      spec.velocity = f.vector_or("velocity", dim::velocity, {});
      if (norm(spec.velocity) > sc.guards.max_speed) {
        throw f.at("velocity")
            .error(fmt::format("a speed of {:.4g} m/s, above the guard's {:g} m/s "
                               "(simulation.guards.max_speed): the run would stop at once",
                               norm(spec.velocity), sc.guards.max_speed));
      }
      spec.start = f.non_negative_or("start", dim::time, 0.0);
      spec.stop = f.has("stop") ? f.positive("stop", dim::time) : std::numeric_limits<double>::infinity();
      if (!(spec.stop > spec.start)) throw f.at("stop").error("expected a stop time after the start");
      spec.seed = f.has("seed") ? static_cast<std::uint64_t>(f.at("seed").integer(0, 1L << 40)) : seed * 1000003ULL + k;
      // The region must hold the largest particle (the factory checks; the error points here).
      double r_max = 0.0;
      for (const auto t : spec.types) r_max = std::max(r_max, sc.types[t].shape.bounding_radius());
      if (f.has("region") && !(spec.region.room() > r_max)) {
        throw f.at("region").error(
            fmt::format("too small for the largest particle (bounding radius {:.3g} mm)", r_max * 1e3));
      }
      sc.factories.push_back(spec);
      sc.factory_enabled.push_back(f.boolean_or("enabled", true));
      factory_names.push_back(name);
      ++k;
    }
  }
  if (const auto ss = root.find("sinks")) {
    for (const auto& [name, s] : ss->entries()) {
      s.allow_only({"region", "enabled"});
      sc.sinks.push_back({name, read_region(s.at("region")), s.boolean_or("enabled", true)});
      sink_names.push_back(name);
    }
  }

  // --- sensors --------------------------------------------------------------------------------
  if (const auto ss = root.find("sensors")) {
    for (const auto& [name, s] : ss->entries()) {
      SensorSpec spec;
      spec.name = name;
      const std::string kind = s.at("kind").choice({"region", "part", "heap", "flow"});
      if (kind == "region") {
        s.allow_only({"kind", "region", "volume", "top"});
        spec.region = read_region(s.at("region"));
        require_inside(s.at("region"), spec.region.lo(), spec.region.hi(), sc.domain, "the sensor's region");
        spec.reference_volume = s.positive_or("volume", dim::volume, 0.0);
        if (s.has("top")) {
          if (spec.reference_volume > 0.0)
            throw s.at("top").error("a region that follows a part has no fixed 'volume'");
          spec.top_part = index_in(s.at("top"), part_names, "part");
        }
      } else if (kind == "part") {
        s.allow_only({"kind", "part", "axis", "area"});
        spec.kind = SensorSpec::Kind::part;
        spec.part = index_in(s.at("part"), part_names, "part");
        spec.axis = s.has("axis") ? unit_vector(s.at("axis")) : Vec3{0, 0, -1};
        spec.area = s.positive_or("area", dim::area, 0.0);
      } else if (kind == "flow") {
        s.allow_only({"kind", "point", "normal", "window"});
        spec.kind = SensorSpec::Kind::flow;
        spec.point = s.vector_or("point", dim::length, {});
        spec.normal = s.has("normal") ? unit_vector(s.at("normal")) : Vec3{0, 0, -1};
        spec.window = s.positive_or("window", dim::time, 0.05);
      } else {
        s.allow_only({"kind", "centre", "radius", "rings"});
        spec.kind = SensorSpec::Kind::heap;
        spec.centre = s.vector_or("centre", dim::length, {});
        spec.outer = s.positive("radius", dim::length);
        spec.rings = s.has("rings") ? static_cast<int>(s.at("rings").integer(2, 10000)) : 20;
      }
      sc.sensors.push_back(spec);
    }
  }
  const std::vector<std::string> values = sc.value_names();

  // --- stages ---------------------------------------------------------------------------------
  for (const ScenarioNode& s : root.at("stages").items()) {
    s.allow_only({"name", "enabled", "time_step", "enable", "disable", "motions", "until"});
    StageSpec stage;
    stage.name = s.at("name").text();
    if (std::any_of(sc.stages.begin(), sc.stages.end(), [&](const StageSpec& x) { return x.name == stage.name; })) {
      throw s.at("name").error("a second stage named '" + stage.name +
                               "': results and reports name stages, so each "
                               "name must be unique");
    }
    stage.enabled = s.boolean_or("enabled", true);
    if (s.has("time_step")) stage.dt = read_time_step(s, sc.rayleigh_step, stage.time_step_fraction);
    for (const auto& [key, on] : {std::pair<const char*, bool>{"enable", true}, {"disable", false}}) {
      if (const auto list = s.find(key)) {
        // factories, sinks and parts by name (one list of all, so a typo is matched against all)
        std::vector<std::string> all = factory_names;
        all.insert(all.end(), sink_names.begin(), sink_names.end());
        all.insert(all.end(), part_names.begin(), part_names.end());
        for (const ScenarioNode& item : list->items()) {
          const std::size_t k = index_in(item, all, "factory, sink or part");
          if (k < factory_names.size()) {
            stage.factories.emplace_back(k, on);
          } else if (k < factory_names.size() + sink_names.size()) {
            stage.sinks.emplace_back(k - factory_names.size(), on);
          } else {
            stage.parts.emplace_back(k - factory_names.size() - sink_names.size(), on);
          }
        }
      }
    }
    if (const auto motions = s.find("motions")) {
      for (const auto& [pname, list] : motions->entries()) {
        const std::size_t part = index_named(list, pname, part_names, "part");
        Motion motion = read_motion(list);
        try {  // what the part's shape allows, as Simulation::set_motion will check
          validate_motion(sc.parts[part].shape, motion);
        } catch (const InputError& e) {
          throw list.error(e.problem());
        }
        stage.motions.emplace_back(part, std::move(motion));
      }
    }
    const ScenarioNode until = s.at("until");
    until.allow_only(
        {"time", "kinetic_energy", "factories_done", "servo_held", "reached", "stable", "min_time", "max_time"});
    if (until.has("time")) stage.duration = until.positive("time", dim::time);
    if (until.has("kinetic_energy")) stage.kinetic_energy = until.positive("kinetic_energy", dim::energy);
    stage.factories_done = until.boolean_or("factories_done", false);
    if (const auto sh = until.find("servo_held")) {
      sh->allow_only({"part", "hold"});
      stage.servo_part = index_in(sh->at("part"), part_names, "part");
      stage.servo_hold = sh->non_negative_or("hold", dim::time, 0.0);
      bool servo = sc.parts[*stage.servo_part].motion.has_servo;
      for (const auto& [p, m] : stage.motions) servo = servo || (p == *stage.servo_part && m.has_servo);
      if (!servo) throw sh->at("part").error("this part has no servo (motion: - servo: ...)");
    }
    if (const auto r = until.find("reached")) {
      r->allow_only({"value", "above", "below"});
      stage.reached = values[index_in(r->at("value"), values, "value")];
      const std::string side = r->one_of({"above", "below"});
      stage.reached_above = side == "above";
      stage.reached_threshold = value_from_si(*stage.reached, r->at(side).quantity(value_dimension(*stage.reached)));
    }
    if (const auto sb = until.find("stable")) {
      sb->allow_only({"value", "tolerance", "window"});
      stage.stable = values[index_in(sb->at("value"), values, "value")];
      if (sb->has("tolerance")) stage.stable_tolerance = sb->at("tolerance").quantity(dim::dimensionless);
      stage.stable_window = sb->positive_or("window", dim::time, 0.05);
    }
    stage.min_time = until.non_negative_or("min_time", dim::time, 0.0);
    if (until.has("max_time")) stage.max_time = until.positive("max_time", dim::time);
    if (!stage.duration && !std::isfinite(stage.max_time)) {
      throw until.error("expected 'time' or 'max_time': every stage needs a time limit");
    }
    sc.stages.push_back(std::move(stage));
  }
  if (std::none_of(sc.stages.begin(), sc.stages.end(), [](const StageSpec& x) { return x.enabled; }))
    throw root.at("stages").error("expected at least one stage that is not skipped (enabled: false)");
  check_step_count(sc, root.at("stages"));

  // --- results --------------------------------------------------------------------------------
  if (const auto rs = root.find("results")) {
    for (const auto& [name, r] : rs->entries()) {
      ResultSpec spec{name, r.text()};
      // Checked now against every stage and value name, with stand-in values (distinct, so
      // that a difference of two values is not zero).
      double stand_in = 1.0;
      try {
        evaluate_result(spec, [&](const std::string& stage, const std::string& value) {
          const bool known_stage =
              std::any_of(sc.stages.begin(), sc.stages.end(), [&](const StageSpec& x) { return x.name == stage; });
          if (!known_stage) {
            std::vector<std::string> stages;
            for (const auto& x : sc.stages) stages.push_back(x.name);
            throw InputError("unknown stage '" + stage + "'" + did_you_mean(stage, stages));
          }
          const bool own = value == "start" || value == "end" || value == "duration";
          if (!own && std::find(values.begin(), values.end(), value) == values.end()) {
            throw InputError("unknown value '" + value + "'" + did_you_mean(value, values) +
                             " (a stage has start, end, duration and every value of the run)");
          }
          return stand_in += 0.0137;
        });
      } catch (const InputError& e) {
        throw r.error(e.problem());
      }
      sc.results.push_back(std::move(spec));
    }
  }

  // --- outputs --------------------------------------------------------------------------------
  // Outputs are written at checks (scenario_run.cpp), so that what is written never changes
  // what is simulated: an interval shorter than the checks' could not be kept.
  auto not_below_checks = [&](const ScenarioNode& node, double interval) {
    if (interval < sc.check_interval * (1.0 - 1e-9)) {
      throw node.at("interval")
          .error(fmt::format(
              "expected an interval of at least simulation.check_interval ({:g} ms), got {:g} ms: outputs are written "
              "at checks, so that they never change what is simulated (a shorter simulation.check_interval allows it)",
              sc.check_interval * 1e3, interval * 1e3));
    }
  };
  if (const auto out = root.find("outputs")) {
    out->allow_only({"timeseries", "frames"});
    if (const auto ts = out->find("timeseries")) {
      ts->allow_only({"interval", "values"});
      sc.outputs.series_interval = ts->positive_or("interval", dim::time, 0.01);
      if (ts->has("interval")) not_below_checks(*ts, sc.outputs.series_interval);
      if (const auto v = ts->find("values")) {
        for (const ScenarioNode& item : v->items())
          sc.outputs.series.push_back(values[index_in(item, values, "value")]);
      }
    }
    if (const auto fr = out->find("frames")) {
      fr->allow_only({"interval"});
      sc.outputs.frame_interval = fr->positive("interval", dim::time);
      not_below_checks(*fr, sc.outputs.frame_interval);
    }
  }
  sc.document = std::move(document);
  return sc;
}

}  // namespace bushel
