#pragma once
// The read side of a run's summary.json (scenario_run.hpp writes it): what `bushel report`
// and the analysis commands take from a finished (or interrupted) run directory.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bushel/scenario/scenario_run.hpp"

namespace bushel {

/// One result of the scenario's `results:` section.
struct RunResult {
  std::string name;
  std::optional<double> value;  ///< [unit]; empty when the run could not compute it
  std::string unit;             ///< "kg/m3", "Pa", "deg", "" for plain numbers: SI except angles
  /// Why the value means little, if it does: a density of a region sensor that was not full
  /// (its top above the grain surface); "" otherwise.
  std::string not_full{};
};

/// What one factory created, per particle type.
struct FactoryTypeSummary {
  std::string type;
  std::size_t count = 0;
  double mass = 0.0;             ///< [kg]
  double fraction = 0.0;         ///< of the factory's total, by mass or count as it was asked
  double target_fraction = 0.0;  ///< what the scenario asked for
};

struct FactorySummary {
  std::string name;
  bool by_mass = true;  ///< shares by mass (else by count)
  std::size_t count = 0;
  double mass = 0.0;  ///< [kg]
  std::vector<FactoryTypeSummary> types;
};

struct RunSummary {
  std::string directory;                                        ///< the run directory as given
  std::string file;                                             ///< its summary.json
  std::string scenario;                                         ///< the scenario file's path
  std::vector<std::pair<std::string, std::string>> parameters;  ///< as run, in file order (text with units)
  std::vector<std::string> overrides;                           ///< "path=value" from --set
  std::vector<std::string> engines;  ///< the builds that ran it, oldest first; empty in older summaries
  bool interrupted = false;
  double dt = 0.0;                    ///< [s]
  std::size_t steps = 0;              ///< time steps
  double simulated_time = 0.0;        ///< [s]
  double wall_time = 0.0;             ///< [s]
  double particle_steps_per_s = 0.0;  ///< [1/s]
  std::vector<StageReport> stages;    ///< the stages that ran (ended), with values and heap profiles
  std::vector<RunResult> results;
  std::vector<FactorySummary> factories;
  std::vector<std::string> warnings;

  /// The scenario's name: its file name without the extension ("calibration-cup").
  std::string scenario_name() const;
  /// A parameter's text, or nothing if the scenario has no such parameter.
  std::optional<std::string> parameter(const std::string& name) const;
  /// A result by name, or nullptr.
  const RunResult* result(const std::string& name) const;
  /// A stage by name, or nullptr (not run, or not in the scenario).
  const StageReport* stage(const std::string& name) const;
  /// The points (x, y) of the results X_K and Y_K that share a suffix K and both have a value
  /// ("pressure_3", "bulk_density_3"), sorted by x: the convention of docs/report.md.
  std::vector<std::pair<double, double>> curve(const std::string& x, const std::string& y) const;
};

/// True if `path` names what read_run_summary reads, a folder or a .json file, rather than
/// something else (a table, a quantity).
bool names_run(const std::string& path);

/// Reads `path`/summary.json (or `path` itself if it names a .json file). Throws InputError
/// naming the file (and the key) if it is missing, is not JSON or is not a bushel summary.
RunSummary read_run_summary(const std::string& path);

}  // namespace bushel
