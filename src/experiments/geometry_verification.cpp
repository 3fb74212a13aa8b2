// Checks of the geometry system (docs/physics.md section 6, issue "Geometry"): contacts with
// meshes against the analytic plane, a scheduled rotation, and a servo lid on a bed.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bushel/experiments/pour_scene.hpp"
#include "bushel/experiments/verification.hpp"
#include "verification_common.hpp"

namespace bushel::verification {
using namespace detail;
namespace {

// A sphere settled on `floor` at (x, y); returns the floor's force along z [N].
double settled_load(Part floor, double x, double y, bool quick) {
  const double g = 9.81;
  const ParticleType type = sphere();
  const double dt = 0.2 * rayleigh(radius);
  Simulation sim(settings(dt, {0.5, 0.27, 0.01}, {0, 0, -g}));
  sim.add_part(std::move(floor));
  const auto t = sim.add_type(type);
  sim.add_body(t, {{x, y, radius + 1e-4}, {}, {}, {}});
  sim.step(quick ? 20'000 : 50'000);
  return -sim.part(0).force.z;  // the sphere pushes the floor down
}

Part mesh_floor(double cell) {
  // 8 x 8 cells: vertices at multiples of `cell`, diagonals from (i, j) to (i + 1, j + 1).
  return make_part("floor", MeshSpec{square_mesh(8 * cell, 8), "square mesh"}, materials::steel());
}

}  // namespace

std::vector<CheckResult> mesh_contact(const Options& o) {
  std::vector<CheckResult> out;
  const double weight = sphere().mass() * 9.81, cell = 5e-3;
  out.push_back(
      result("resting on a plane: load", "-F_z [N]", weight, settled_load(floor_wall(), 0, 0, o.quick), 1e-6));
  const struct {
    const char* where;
    double x, y;
  } spots[] = {{"a mesh face", 0.3 * cell, 0.7 * cell},
               {"a mesh edge", 0.5 * cell, 0.0},
               {"a mesh diagonal edge", 0.4 * cell, 0.4 * cell},
               {"a mesh vertex (6 triangles)", 0.0, 0.0}};
  for (const auto& s : spots) {
    out.push_back(result(fmt::format("resting on {}: load", s.where), "-F_z [N]", weight,
                         settled_load(mesh_floor(cell), s.x, s.y, o.quick), 1e-6));
  }
  // Rolling across the triangles (obliquely, over edges and vertices): the floor's load may
  // not jump where the contact passes from one triangle to the next.
  const double g = 9.81, dt = 0.2 * rayleigh(radius);
  for (const bool mesh : {false, true}) {
    Simulation sim(settings(dt, {0.5, 0.5, 0.0}, {0, 0, -g}));
    sim.add_part(mesh ? make_part("floor", MeshSpec{square_mesh(0.2, 40), "square mesh"}, materials::steel())
                      : floor_wall());
    const auto t = sim.add_type(sphere());
    const double z = radius - resting_overlap(sphere(), g), v = 0.3;
    const Vec3 dir = normalized(Vec3{1.0, 0.37, 0.0});
    sim.add_body(t, {{-0.05, -0.02, z}, {}, v * dir, (v / z) * cross(Vec3{0, 0, 1}, dir)});
    sim.step(2000);  // let the start settle
    double worst = 0.0;
    const auto n = static_cast<std::uint64_t>((o.quick ? 0.1 : 0.3) / dt);
    for (std::uint64_t k = 0; k < n; ++k) {
      sim.step();
      worst = std::max(worst, std::abs(-sim.part(0).force.z - weight));
    }
    out.push_back(result(fmt::format("rolling across {}: largest load change", mesh ? "mesh triangles" : "a plane"),
                         "|-F_z - m g| / m g [-]", 0.0, worst / weight, 1e-3));
  }
  // Thrown sideways on a slope (gravity tilted by atan 0.2, below the friction angle): the
  // sphere slides, starts rolling, and rolls up and back across the triangles with static
  // friction turning it. That tangential spring must carry over from triangle to triangle
  // (history per sphere and part), so the path is the plane's to rounding.
  Vec3 stop[2];
  for (const bool mesh : {false, true}) {
    const Vec3 tilted{0.2 * g, 0.0, -g};  // tan = 0.2 < mu_s = 0.5
    Simulation sim(settings(dt, {0.5, 0.5, 0.0}, tilted));
    sim.add_part(mesh ? make_part("floor", MeshSpec{square_mesh(0.2, 40), "square mesh"}, materials::steel())
                      : floor_wall());
    const auto t = sim.add_type(sphere());
    const double z = radius - resting_overlap(sphere(), std::hypot(tilted.x, tilted.z));
    sim.add_body(t, {{-0.011, 0.0023, z}, {}, {-0.25, 0.1, 0.0}, {}});
    sim.step(static_cast<std::uint64_t>((o.quick ? 0.15 : 0.3) / dt));
    stop[mesh ? 1 : 0] = sim.particles().position[0];
  }
  out.push_back(result("sliding and rolling on a slope across mesh triangles: end point vs the plane's", "|dx| [m]",
                       0.0, norm(stop[1] - stop[0]), 1e-9));
  return out;
}

std::vector<CheckResult> gate_turn(const Options&) {
  // The study's funnel gate: 180 degrees at 7.85 rad/s from t = 0.6 s, with a time step that
  // does not divide the schedule.
  Simulation sim(settings(3.3e-5, {0.5, 0.27, 0.01}));
  Part gate = make_part("gate", PlateSpec{0.06, 0.03}, materials::steel(), {{0.0, 0.015, 0.0}, {}});
  gate.motion.segments.push_back(MotionSegment::turn({1, 0, 0}, {0, 0, 0}, pi, 7.85, 0.6));
  sim.add_part(std::move(gate));
  auto angle = [&] {  // of the plate's normal from +z, about +x
    const Vec3 n = rotate(sim.part(0).pose.orientation, Vec3{0, 0, 1});
    return std::atan2(-n.y, n.z);
  };
  sim.step(static_cast<std::uint64_t>(0.6 / 3.3e-5));
  const double before = std::abs(angle());
  sim.step(static_cast<std::uint64_t>((0.6 + 0.5 * pi / 7.85) / 3.3e-5) - sim.steps());
  const double half_way = std::abs(7.85 * (sim.time() - 0.6) - angle());
  sim.step(static_cast<std::uint64_t>(1.2 / 3.3e-5) - sim.steps());
  const double turned = std::abs(angle());
  return {result("gate before its start: angle", "angle [rad]", 0.0, before, 1e-12),
          result("gate while turning: angle - 7.85 rad/s x t", "angle error [rad]", 0.0, half_way, 1e-9),
          result("gate after its turn: angle", "angle [rad]", pi, turned, 1e-9),
          result("gate after its turn: hinge still", "y of the plate centre [m]", -0.015, sim.part(0).pose.position.y,
                 1e-9)};
}

std::vector<CheckResult> servo_hold(const Options& o) {
  // A settled bed of spheres in a cylinder; a lid comes down under servo control to 10 kPa
  // and must then hold it within 1%.
  PourSpec spec;
  spec.count = o.quick ? 400 : 1500;
  spec.container_diameter = o.quick ? 0.030 : 0.045;
  PourScene scene = make_pour_scene(spec);
  Simulation& sim = scene.simulation;
  const double dt = sim.settings().dt;
  sim.step(static_cast<std::uint64_t>(0.5 / dt));
  double top = 0.0;
  const auto& ps = sim.particles();
  for (std::size_t b = 0; b < ps.bodies(); ++b) top = std::max(top, ps.position[b].z + 1.82e-3);
  const double r = scene.container_radius - 0.2e-3, area = pi * r * r, pressure = 10e3;
  Part lid = make_part("lid", DiscSpec{r}, materials::steel(), {{0, 0, top + 1e-3}, {}});
  lid.motion.has_servo = true;
  lid.motion.servo.axis = {0, 0, -1};
  lid.motion.servo.target_force = pressure * area;
  lid.motion.servo.area = area;
  lid.motion.servo.max_speed = 0.02;
  lid.motion.servo.gain = 0.02 / (0.1 * pressure * area);  // full speed at 10% off the target
  lid.motion.servo.start = sim.time();
  const std::size_t l = sim.add_part(std::move(lid));
  // Reached: within the tolerance without a break for 0.1 s (the bed under the lid settles
  // into the new load first), at the latest 0.6 s after the lid starts.
  const double limit = sim.time() + 0.6;
  auto steady = [&] { return sim.part(l).servo.held && sim.time() - sim.part(l).servo.held_since >= 0.1; };
  while (!steady() && sim.time() < limit) sim.step(100);
  const bool reached = steady();
  double worst = 0.0;
  const auto n = static_cast<std::uint64_t>((o.quick ? 0.1 : 1.0) / dt);
  for (std::uint64_t k = 0; k < n; ++k) {
    sim.step();
    worst = std::max(worst, std::abs(sim.part(l).servo.measured_force / area - pressure) / pressure);
  }
  return {result("servo lid reaches 10 kPa steadily (0.1 s) within 0.6 s", "reached [1 = yes]", 1.0,
                 reached ? 1.0 : 0.0, 0.0),
          result(fmt::format("servo lid holds 10 kPa for {:g} s", o.quick ? 0.1 : 1.0), "|p - 10 kPa| / 10 kPa [-]",
                 0.0, worst, 0.01)};
}

}  // namespace bushel::verification
