#include "run_state.hpp"

#include <algorithm>

#include "sensor_readings.hpp"

namespace bushel::scenario_running {

Motion shifted(Motion m, double t0) {
  for (auto& s : m.segments) s.start += t0, s.end += t0;
  m.servo.start += t0;
  m.servo.end += t0;
  return m;
}

namespace {

SimulationSettings with_threads(SimulationSettings s, ThreadPolicy threads) {
  s.threads = threads;
  return s;
}

}  // namespace

RunState::RunState(const Scenario& s, ThreadPolicy threads)
    : sc(s), sim(with_threads(s.settings, threads)), factory_on(s.factory_enabled) {
  for (const auto& t : sc.types) {
    sim.add_type(t);
    type_names.push_back(t.name);
  }
  for (const auto& p : sc.parts) sim.add_part(p);
  for (const auto& f : sc.factories) factories.emplace_back(f, sim);
  for (const auto& k : sc.sinks) sinks.push_back({k.name, k.region, k.enabled, {}, {}});
  for (const auto& k : sc.sensors) {
    if (const auto* f = k.as<FlowSensorSpec>()) flows.emplace_back(f->point, f->normal, f->window);
  }
  for (std::size_t i = 0, flow = 0; i < sc.sensors.size(); ++i) {
    flow_of.push_back(sc.sensors[i].as<FlowSensorSpec>() ? &flows[flow++] : nullptr);
  }
  names = sc.value_names();
}

// The global values, in the order of global_value_names().
std::vector<double> RunState::global_values() const {
  const ParticleSystem& ps = sim.particles();
  std::vector<double> v;
  v.reserve(names.size());
  double potential = 0.0, created = 0.0, removed = 0.0;
  for (std::size_t b = 0; b < ps.bodies(); ++b) potential -= ps.mass(b) * dot(sc.settings.gravity, ps.position[b]);
  for (const auto& f : factories) created += f.report().total_mass;
  for (const auto& s : sinks) {
    for (const double m : s.mass) removed += m;
  }
  const double ke = ps.kinetic_energy();
  const auto n = static_cast<double>(ps.bodies());
  v = {sim.time(),
       n,
       ke,
       n > 0 ? ke / n : 0.0,
       potential,
       sim.max_overlap_ratio(),
       sim.unbalanced_force_ratio(),
       static_cast<double>(sim.contacts()),
       created,
       removed,
       lost.total_mass(),
       static_cast<double>(lost.total_count())};
  return v;
}

// Where the value `name` ("cup.bulk_density" or a global) is; found once, read at every check.
RunState::ValueRef RunState::find(const std::string& name) const {
  const auto& g = global_value_names();
  if (const auto it = std::find(g.begin(), g.end(), name); it != g.end()) {
    return {ValueRef::none, static_cast<std::size_t>(it - g.begin())};
  }
  for (std::size_t i = 0; i < sc.sensors.size(); ++i) {
    const SensorSpec& s = sc.sensors[i];
    const auto own = s.values(type_names);
    if (const auto it = std::find(own.begin(), own.end(), name.substr(std::min(name.size(), s.name.size() + 1)));
        name.starts_with(s.name + ".") && it != own.end()) {
      return {i, static_cast<std::size_t>(it - own.begin())};
    }
  }
  return {};  // (names were checked by read_scenario)
}

std::string echo_text(const ScenarioDocument& doc) {
  YAML::Emitter echo;
  echo << doc.root;
  return echo.c_str();
}

std::uint64_t state_hash(const ParticleSystem& ps) {
  std::uint64_t h = 1469598103934665603ULL;
  auto mix = [&](const auto& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    for (std::size_t i = 0; i < v.size() * sizeof(v[0]); ++i) h = (h ^ p[i]) * 1099511628211ULL;
  };
  mix(ps.body_id);
  mix(ps.position);
  mix(ps.velocity);
  mix(ps.angular_momenta());
  mix(ps.orientations());
  return h;
}

}  // namespace bushel::scenario_running
