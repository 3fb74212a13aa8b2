#include "bushel/experiments/funnel_scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "bushel/core/input_error.hpp"
#include "bushel/experiments/pour_scene.hpp"

namespace bushel {
namespace {

constexpr double gate_gap = 0.5e-3;  // between the outlet and the closed gate [m]

}  // namespace

TriangleMesh funnel_mesh(const FunnelSpec& spec, int segments) {
  return tessellate(faces_of(ConeSpec::funnel(spec.top_diameter, spec.outlet_diameter, spec.wall_angle)), segments);
}

FunnelScene make_funnel_scene(const FunnelSpec& spec) {
  if (spec.count == 0) throw InputError("expected at least one particle").with_key("count");
  if (!(spec.gate_speed > 0.0)) throw InputError("expected a positive gate speed in rad/s").with_key("gate_speed");
  if (!(spec.gate_open_time >= 0.0)) throw InputError("expected a time >= 0 s").with_key("gate_open_time");
  const ConeSpec cone = ConeSpec::funnel(spec.top_diameter, spec.outlet_diameter, spec.wall_angle);
  ParticleType type = wheat_particle(spec.particle);
  const double dt = spec.dt_fraction * rayleigh_step(type);
  const double d = 2.0 * type.shape.bounding_radius();
  FunnelScene scene{Simulation(wheat_settings(dt)), 0.0, -gate_gap, 0, 0};
  Simulation& sim = scene.simulation;
  const Material steel = materials::steel();
  scene.funnel = spec.mesh ? sim.add_part(make_part("funnel", MeshSpec{*spec.mesh, "funnel mesh"}, steel))
                           : sim.add_part(make_part("funnel", cone, steel));
  // A square gate under the outlet, hinged on its +y edge: turning by pi about +x swings it
  // down and over to the far side of the hinge.
  const double half = 0.75 * spec.outlet_diameter;
  Part gate = make_part("gate", PlateSpec{2 * half, 2 * half}, steel, {{0, 0, scene.gate_z}, {}});
  gate.motion.segments.push_back(
      MotionSegment::turn({1, 0, 0}, {0, half, scene.gate_z}, std::numbers::pi, spec.gate_speed, spec.gate_open_time));
  scene.gate = sim.add_part(std::move(gate));
  // Grain that has left falls onto a floor well below, out of the way.
  sim.add_part(plane_part("floor", steel, {0, 0, -0.15}, {0, 0, 1}));
  // The grain starts as a loose cloud above the funnel, within 80% of its top radius.
  const double exclusion = 1.013 * d;
  const auto t = sim.add_type(std::move(type));
  std::mt19937_64 rng(spec.seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> n01;
  for (const Vec3& p : random_cloud(spec.count, 0.8 * cone.top_radius, exclusion, 0.3, spec.seed)) {
    const Quat q = normalized(Quat{n01(rng), n01(rng), n01(rng), n01(rng)});
    sim.add_body(t, {p + Vec3{0, 0, cone.height + 2e-3}, q, {}, {}});
  }
  return scene;
}

double discharged_mass(const FunnelScene& scene) {
  const auto& p = scene.simulation.particles();
  double m = 0.0;
  for (std::size_t b = 0; b < p.bodies(); ++b) m += p.position[b].z < scene.gate_z ? p.mass(b) : 0.0;
  return m;
}

}  // namespace bushel
