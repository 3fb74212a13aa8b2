#pragma once
// Runs a validated scenario: its stages in order, factories and sinks acting every check
// interval, stage conditions checked as often, and the outputs written into one folder:
//   summary.json    the scenario echo (with its overrides), each stage's end values and
//                   what ended it, what the factories created and the sinks removed, dt,
//                   steps, wall time, particle-steps per second, warnings (written atomically)
//   timeseries.csv  the chosen values at the chosen interval
//   frames/         ParaView frames (particles and geometry, .vtu + .pvd), if asked for
//   checkpoint.bin  the whole state of the run, written atomically every few minutes of wall
//                   time and on Ctrl-C; `--restart` continues from it bit for bit (the
//                   scenario itself is kept in it)

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bushel/scenario/run_summary.hpp"
#include "bushel/scenario/scenario.hpp"

namespace bushel {

/// Where a run stands at a check, for RunOptions::on_check.
struct RunProgress {
  std::string stage;        ///< the stage's name
  std::size_t stage_index;  ///< from 0
  std::size_t stages;       ///< how many the scenario has
  double time;              ///< simulated [s]
  std::size_t particles;    ///< bodies in the simulation
  std::uint64_t steps;      ///< since the run began
  double wall_time;         ///< since the run began, over all its sittings [s]
};

struct RunOptions {
  std::string out_dir;  ///< created if missing
  /// A fresh run into a folder that holds another run's outputs replaces them (they are removed
  /// first); false: such a folder is an InputError.
  bool overwrite = false;
  int threads = 0;                   ///< 0: the scenario's setting
  bool progress = true;              ///< a progress line on stderr
  double progress_interval = 10;     ///< wall seconds between plain progress lines (not a terminal) [s]
  double checkpoint_interval = 300;  ///< wall seconds between checkpoints [s]; 0 = only on Ctrl-C
  /// Stop as Ctrl-C would at the first check at or after this simulated time [s] (tests).
  double interrupt_at = std::numeric_limits<double>::infinity();
  /// Called at every check, after its outputs (from the thread that called run_scenario). It
  /// sees the run and cannot change it; returning true stops the run there as Ctrl-C would
  /// (checkpoint written, RunReport::interrupted with signal 0).
  std::function<bool(const RunProgress&)> on_check;
};

struct RunReport {
  bool interrupted = false;   ///< stopped by Ctrl-C (or interrupt_at): checkpoint.bin holds the rest
  bool at_stop_time = false;  ///< stopped because it reached RunOptions::interrupt_at, as asked
  int signal = 0;             ///< the signal that interrupted it (SIGINT, SIGTERM); 0: none
  std::string failed;         ///< why a guard stopped the run (run_guards.hpp); "" if none did
  std::vector<StageReport> stages;
  std::uint64_t steps = 0;
  double simulated_time = 0.0;  ///< [s]
  double wall_time = 0.0;       ///< [s]
  double particle_steps = 0.0;  ///< sum over steps of the particle count
  std::vector<std::string> warnings;
  std::vector<std::string> engines;  ///< the builds that ran it, oldest first (build_description())
  /// What summary.json holds (its warnings: these, then the results'); its directory and file
  /// are RunOptions::out_dir and the summary.json there.
  RunSummary summary;
};

/// Runs the scenario and writes its outputs; returns what summary.json holds.
RunReport run_scenario(const Scenario& scenario, const RunOptions& options);

/// Continues the run whose checkpoint is in options.out_dir (the scenario comes from it).
/// Throws InputError if there is no readable checkpoint.
RunReport resume_scenario(const RunOptions& options);

/// How far [m] the grain surface lay below the top of region sensor `sensor` at the end of
/// stage `r` (its `surface_margin`, negated), if it did: the region was not full and a density
/// over it counts empty space; nothing if it was full or is not a region sensor.
std::optional<double> surface_shortfall(const StageReport& r, const std::string& sensor);

}  // namespace bushel
