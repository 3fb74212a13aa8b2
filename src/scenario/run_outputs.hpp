#pragma once
// A run's outputs as it goes: its folder, timeseries.csv and the progress lines on stderr
// (frames are io::FrameWriter's; summary.json is run_results.hpp's). Internal to src/scenario.

#include <chrono>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "bushel/core/sample_window.hpp"
#include "bushel/integrate/simulation.hpp"
#include "bushel/scenario/scenario_run.hpp"

namespace bushel::scenario_running {

/// A fresh run's output folder: created, or refused if it holds another run's outputs unless
/// the run may replace them, which are then removed first (so that no old frame or row is
/// left beside the new ones, and a kill cannot leave two runs mixed).
void clear_output(const RunOptions& o);

/// Creates the output folder, and sets the run's thread count.
void prepare_output(const RunOptions& o);
/// The scenario's thread policy, or a fixed count where the options give one.
ThreadPolicy thread_policy(const Scenario& sc, const RunOptions& o);

/// timeseries.csv: a header, then a row at each of the scenario's intervals; beside it
/// timeseries.units.csv, a row per column: its name and unit.
class SeriesWriter {
 public:
  /// Opens `out_dir`/timeseries.csv for the values `chosen` among the scenario's (all if none
  /// are chosen). A fresh run writes the header and the units, and sets `bytes` to the
  /// file's size; a continued one cuts the file to `bytes`, where its checkpoint was (the
  /// rows after it are written again).
  void open(const std::string& out_dir, const Scenario& sc, const std::vector<std::string>& names,
            const std::vector<std::string>& chosen, bool resume, std::uint64_t& bytes);
  /// A row: the stage, then the chosen ones of `values` (in the order of `names`). Returns the
  /// file's size after it.
  std::uint64_t write_row(const std::string& stage, const std::vector<double>& values);

 private:
  std::vector<std::size_t> columns_;
  std::ofstream out_;
};

/// The progress lines on stderr (RunOptions::progress): one every progress_interval of wall
/// time (4 a second, rewritten in place, on a terminal), each stage's end, how the run
/// stopped.
class Progress {
 public:
  using Clock = std::chrono::steady_clock;
  Progress(const RunOptions& o, std::size_t stages);
  bool on() const { return o_.progress; }
  bool tty() const { return tty_; }
  /// A stage begins, or continues after a restart, at `steps`.
  void stage_entered(std::uint64_t steps);
  /// The line for stage `index`, at most as often as it is due; the stage began at `t0` and
  /// ends at the latest `limit` after it [s].
  void line(const Simulation& sim, const StageSpec& stage, std::size_t index, double t0, double limit);
  void stage_ended(const Simulation& sim, const StageReport& r, std::size_t index);
  void failed(const std::string& why);
  void interrupted(double time);

 private:
  const RunOptions& o_;
  std::size_t stages_;
  bool tty_ = false;
  Clock::time_point last_line_, stage_wall0_;
  SampleWindow recent_steps_;  // (wall s since the stage's start in this sitting, step count)
};

}  // namespace bushel::scenario_running
