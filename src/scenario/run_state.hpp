#pragma once
// What a run keeps besides the simulation (factories, sinks, flow counts) and its values, and
// where it stands between checks (Position): with the simulation's state, what a checkpoint
// holds. Internal to src/scenario.

#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "bushel/core/sample_window.hpp"
#include "bushel/insertion/factory.hpp"
#include "bushel/insertion/sink.hpp"
#include "bushel/integrate/simulation.hpp"
#include "bushel/scenario/run_guards.hpp"
#include "bushel/scenario/scenario_run.hpp"
#include "bushel/sensors/plane_flow.hpp"
#include "sensor_readings.hpp"

namespace bushel::scenario_running {

// Motion times of a stage count from its start.
Motion shifted(Motion m, double t0);

// Everything a run keeps besides the simulation: factories, sinks and what they counted.
struct RunState {
  const Scenario& sc;
  Simulation sim;
  std::vector<Factory> factories;
  std::vector<bool> factory_on;
  std::vector<Sink> sinks;
  Sink lost{"domain", {}, true, {}, {}};
  std::vector<PlaneFlow> flows;           // one per flow sensor, in order
  std::vector<const PlaneFlow*> flow_of;  // each sensor's in `flows`, or null
  std::vector<std::string> type_names, names;

  /// The simulation of `s`, its steps on `threads` (the scenario's, or the command line's).
  RunState(const Scenario& s, ThreadPolicy threads);

  double kinetic_energy_per_particle() const {
    const auto n = sim.particles().bodies();
    return n > 0 ? sim.particles().kinetic_energy() / static_cast<double>(n) : 0.0;
  }

  // The global values, in the order of global_value_names().
  std::vector<double> global_values() const;

  // Sensor i's values, in the order of its columns.
  void append_sensor(std::size_t i, std::vector<double>& v) const {
    append_values(sc.sensors[i], SensorInputs{sim, sc, flow_of[i]}, v);
  }

  // Every value, in the order of `names`.
  std::vector<double> values() const {
    std::vector<double> v = global_values();
    for (std::size_t i = 0; i < sc.sensors.size(); ++i) append_sensor(i, v);
    return v;
  }

  // Every value with its name.
  std::vector<std::pair<std::string, double>> named_values() const {
    const auto v = values();
    std::vector<std::pair<std::string, double>> out;
    for (std::size_t k = 0; k < v.size(); ++k) out.emplace_back(names[k], v[k]);
    return out;
  }

  // Where one value is: a global (no sensor) or a sensor's column.
  struct ValueRef {
    static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
    std::size_t sensor = none;  // none: a global
    std::size_t column = none;  // none: no such value
  };

  // Where the value `name` ("cup.bulk_density" or a global) is; found once, read at every check.
  ValueRef find(const std::string& name) const;

  // One value, reading only what it needs.
  double value(const ValueRef& ref) const {
    if (ref.column == ValueRef::none) return std::numeric_limits<double>::quiet_NaN();
    if (ref.sensor == ValueRef::none) return global_values()[ref.column];
    std::vector<double> v;
    append_sensor(ref.sensor, v);
    return v[ref.column];
  }
};

// Where a run stands between checks: enough, with the simulation's state, to continue it.
struct Position {
  std::uint64_t stage = 0;                  // index of the current stage
  bool stage_started = false;               // its actions (switches, motions) are done
  double t0 = 0.0;                          // its start [s]
  std::uint64_t steps0 = 0;                 // steps at its start
  SampleWindow history;                     // the stable condition's samples
  double next_row = 0.0, next_frame = 0.0;  // [s]
  double particle_steps = 0.0;
  double wall_before = 0.0;        // wall time of earlier sittings [s]
  std::uint64_t series_bytes = 0;  // timeseries.csv up to the last row
  std::vector<StageReport> done;   // stages finished
  std::vector<std::string> warnings;
  double peak_overlap = 0.0;  // the current stage's largest overlap over the smaller radius
  std::vector<std::pair<std::string, double>> deep_overlaps;  // stages whose peak passed the warning's
  std::vector<std::string> engines;  // the builds that ran it, oldest first (build_description)
  GuardClock guards;                 // what the guards remember between checks
  std::string failed;                // why a guard stopped the run; "" while none has
};

// The scenario as resolved (overrides applied, parameters substituted), as YAML text.
std::string echo_text(const ScenarioDocument& doc);

// FNV-1a over the bits of the bodies' state: equal hashes, equal runs (restart, threads).
std::uint64_t state_hash(const ParticleSystem& ps);

}  // namespace bushel::scenario_running
