#pragma once
// A scenario read and validated: everything a run needs, in SI, with every name resolved
// to an index. read_scenario checks the whole file before a single step runs (docs/
// scenarios.md lists the sections and keys); an error names the file, line and key.

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bushel/geometry/part.hpp"
#include "bushel/geometry/region.hpp"
#include "bushel/insertion/factory.hpp"
#include "bushel/integrate/critical_step.hpp"
#include "bushel/integrate/simulation.hpp"
#include "bushel/scenario/frame_writer.hpp"
#include "bushel/scenario/run_guards.hpp"
#include "bushel/scenario/scenario_document.hpp"
#include "bushel/scenario/sensor_spec.hpp"
#include "bushel/units/expression.hpp"

namespace bushel {

struct SinkSpec {
  std::string name;
  Region region;
  bool enabled = true;  ///< at the start of the run
};

/// How a time step was given: a time, or a fraction of the smallest element's Rayleigh step
/// ("0.2 rayleigh") or of the contacts' critical step ("0.3 critical"; docs/physics.md section 3).
struct TimeStepRule {
  enum class Basis { time, rayleigh, critical };
  Basis basis = Basis::time;
  double fraction = 0.0;     ///< of the basis's step [-]; 0 for a time
  std::string text() const;  ///< "0.2 rayleigh", "0.3 critical" or "time"
};

/// One stage of a run: what it switches on or off and starts moving, and when it ends (the
/// first condition met; the report says which).
struct StageSpec {
  std::string name;
  bool enabled = true;  ///< false: skipped (a scenario's optional step, "enabled: ${strike}")
  /// Its own time step [s] ("time_step: 0.05 rayleigh" in the stage); none: the simulation's.
  std::optional<double> dt;
  TimeStepRule time_step_rule;                          ///< how its own step was given
  std::vector<std::pair<std::size_t, bool>> factories;  ///< factory index, enabled
  std::vector<std::pair<std::size_t, bool>> sinks;      ///< sink index, enabled
  std::vector<std::pair<std::size_t, bool>> parts;      ///< part index, enabled
  std::vector<std::pair<std::size_t, Motion>> motions;  ///< part index, motion (times from the stage start)
  // --- end conditions ------------------------------------------------------------------------
  std::optional<double> duration;                             ///< ends after this time [s]
  std::optional<double> kinetic_energy;                       ///< ... when the kinetic energy per particle is below [J]
  bool factories_done = false;                                ///< ... when every factory enabled in it is done
  std::optional<std::size_t> servo_part;                      ///< ... when this part's servo has held its force
  double servo_hold = 0.0;                                    ///<     for this long [s]
  std::optional<std::string> reached;                         ///< ... when this value ("sensor.value") has
  double reached_threshold = 0.0;                             ///<     gone above (or below) this [SI; deg for angles]
  bool reached_above = true;                                  ///<     (false: below)
  std::optional<std::string> stable;                          ///< ... when this value ("sensor.value") is stable:
  double stable_tolerance = 0.01;                             ///<     its relative change stays below this [-]
  double stable_window = 0.05;                                ///<     over this time [s]
  double min_time = 0.0;                                      ///< no condition but max_time ends it earlier [s]
  double max_time = std::numeric_limits<double>::infinity();  ///< it ends at the latest after this [s]
};

/// What ended a stage: the first of its end conditions met (StageSpec's, in this order).
enum class StageEnd { time, kinetic_energy, factories_done, servo_held, reached, stable, max_time };

/// Its name in the outputs ("factories_done").
std::string_view to_string(StageEnd end);

struct OutputSpec {
  double series_interval = 0.01;    ///< timeseries.csv row interval [s]
  std::vector<std::string> series;  ///< its columns ("cup.bulk_density"); empty = all values
  double frame_interval = 0.0;      ///< ParaView frames interval [s]; 0 = none
  io::FrameOptions frames;          ///< what the frames hold and their encoding
};

/// A number the run computes from its stages' end values when it ends ("compressibility:
/// (tapped.cup.bulk_density - loose.cup.bulk_density) / tapped.cup.bulk_density").
struct ResultSpec {
  std::string name;
  std::string expression;  ///< units/expression.hpp; names are stage.value or stage.start|end|duration
};

struct Scenario {
  ScenarioDocument document;    ///< the file with its overrides, for the summary
  SimulationSettings settings;  ///< dt filled in from the time step
  TimeStepRule time_step_rule;  ///< how the time step was given
  double rayleigh_step = 0.0;   ///< of the smallest element [s]
  CriticalStep critical_step;   ///< of the contacts of the types and parts (critical_step.hpp)
  std::vector<ParticleType> types;
  std::vector<Part> parts;
  std::vector<FactorySpec> factories;  ///< types index `types`
  std::vector<bool> factory_enabled;   ///< at the start of the run
  std::vector<SinkSpec> sinks;
  Region domain;  ///< particles outside are removed as lost
  std::vector<SensorSpec> sensors;
  std::vector<StageSpec> stages;
  OutputSpec outputs;
  std::vector<ResultSpec> results;
  double check_interval = 1e-3;  ///< factories, sinks, stage conditions and guards act this often [s]
  RunGuards guards;              ///< limits that stop a run gone wrong
  /// Every value the run can report: globals, then each sensor's ("cup.bulk_density").
  std::vector<std::string> value_names() const;
  /// The same with their dimensions, as each sensor kind declares them.
  std::vector<ValueColumn> value_columns() const;
  /// The dimension of one of its values ("cup.bulk_density" is a density, "gate.angle" an
  /// angle), or of a stage's start, end or duration (a time); dimensionless if it has none of
  /// that name.
  units::Dimension value_dimension(const std::string& value_name) const;
  /// A run's values are SI except angles (heap and part), which are in degrees as
  /// timeseries.csv shows them: these convert a value between the run's unit and SI (radians).
  double value_to_si(const std::string& value_name, double value) const;
  double value_from_si(const std::string& value_name, double value_si) const;
};

/// Reads and validates a scenario. Throws InputError (file, line, key) for unknown keys,
/// missing keys, wrong units, sizes that are not positive, parameters out of their physical
/// range, unknown names, and geometry, factories or sensors that do not fit in the domain.
Scenario read_scenario(ScenarioDocument document);

/// The global values every run reports, with their dimensions.
const std::vector<ValueColumn>& global_value_columns();
const std::vector<std::string>& global_value_names();

/// The unit a result is written in: angles in degrees, everything else in SI.
std::string_view result_unit(units::Dimension d);
double result_value(const units::Quantity& q);

/// Evaluates a result's expression; `value` gives a stage's value by its name
/// ("fill.cup.mass", "fill.duration"), or throws InputError for an unknown one; the scenario
/// gives the values' dimensions.
units::Quantity evaluate_result(const ResultSpec& result, const Scenario& scenario,
                                const std::function<double(const std::string& stage, const std::string& value)>& value);

}  // namespace bushel
