#pragma once
// A run's summary: what its summary.json holds, in one type. The run builds it and writes it
// (scenario_run.hpp, which returns it in its RunReport); `bushel report` and the analysis
// commands read it back from a finished (or interrupted) run directory. to_json and from_json
// are the one description of the format.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace bushel {

struct StageReport {
  std::string name;
  std::string ended_by;           ///< what ended it: to_string(StageEnd) (scenario.hpp), "max_time", ...
  double start = 0.0, end = 0.0;  ///< [s]
  std::uint64_t steps = 0;
  std::vector<std::pair<std::string, double>> values;  ///< every value at the stage's end
  /// Each heap sensor's surface at the stage's end: its name, ring radii [m], heights [m]
  /// (NaN where a ring holds no grain).
  struct Profile {
    std::string sensor;
    std::vector<double> radius, height;
  };
  std::vector<Profile> profiles;
  double dt = 0.0;  ///< the time step it ran with [s] (in the summary; a checkpoint does not hold it)
};

/// One result of the scenario's `results:` section.
struct RunResult {
  std::string name;
  std::optional<double> value;  ///< [unit]; empty when the run could not compute it
  std::string unit;             ///< "kg/m3", "Pa", "deg", "" for plain numbers: SI except angles
  /// Why the value means little, if it does: a density of a region sensor that was not full
  /// (its top above the grain surface); "" otherwise.
  std::string not_full{};
  bool computed = true;  ///< false: null in summary.json (its stages did not run, or it failed)
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
  bool done = false;  ///< it created its total
};

/// What a sink (or the domain's boundary, for the particles lost) removed, per particle type.
struct SinkSummary {
  struct Type {
    std::string type;
    std::size_t count = 0;
    double mass = 0.0;  ///< [kg]
  };
  std::string name;
  std::size_t count = 0;
  double mass = 0.0;  ///< [kg]
  std::vector<Type> types;
};

struct RunSummary {
  std::string directory;                                        ///< the run directory as given
  std::string file;                                             ///< its summary.json
  std::string scenario;                                         ///< the scenario file's path
  std::string engine_version, engine_commit;                    ///< the build that wrote it
  bool engine_dirty = false;                                    ///< built with uncommitted changes
  std::vector<std::pair<std::string, std::string>> parameters;  ///< as run, in file order (text with units)
  std::vector<std::string> overrides;                           ///< "path=value" from --set
  std::vector<std::string> engines;  ///< the builds that ran it, oldest first; empty in older summaries
  std::string echo;                  ///< the scenario as resolved, as YAML text
  bool interrupted = false;
  std::string failed;                 ///< why a guard stopped the run; "" if none did
  double dt = 0.0;                    ///< [s]
  double rayleigh_step = 0.0;         ///< of the smallest element [s]
  double critical_step = 0.0;         ///< of the contacts (critical_step.hpp) [s]; 0 in older summaries
  std::string time_step_rule;         ///< "0.2 rayleigh", "0.3 critical" or "time"; "" in older summaries
  std::size_t steps = 0;              ///< time steps
  double simulated_time = 0.0;        ///< [s]
  double wall_time = 0.0;             ///< [s]
  double particle_steps_per_s = 0.0;  ///< [1/s]
  std::vector<StageReport> stages;    ///< the stages that ran (ended), with values and heap profiles
  std::vector<RunResult> results;
  std::vector<FactorySummary> factories;
  std::vector<SinkSummary> sinks;
  SinkSummary lost;                                          ///< the particles that left the domain
  std::vector<std::pair<std::string, double>> final_values;  ///< every value at the end (NaN: none)
  std::string final_state_hash;  ///< of the bodies' state bits, in hex: equal hashes, equal runs
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

/// summary.json's content, its keys in the order the file has them.
void to_json(nlohmann::ordered_json& j, const RunSummary& s);
/// Reads what to_json writes, and older summaries (without the keys added since). Throws
/// InputError naming the key for a missing key or one of another kind.
void from_json(const nlohmann::ordered_json& j, RunSummary& s);

/// Writes `s` as `dir`/summary.json (atomically).
void write_run_summary(const RunSummary& s, const std::string& dir);

/// True if `path` names what read_run_summary reads, a folder or a .json file, rather than
/// something else (a table, a quantity).
bool names_run(const std::string& path);

/// Reads `path`/summary.json (or `path` itself if it names a .json file). Throws InputError
/// naming the file (and the key) if it is missing, is not JSON or is not a bushel summary.
RunSummary read_run_summary(const std::string& path);

}  // namespace bushel
