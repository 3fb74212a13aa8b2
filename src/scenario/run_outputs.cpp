#include "run_outputs.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "bushel/core/input_error.hpp"
#include "bushel/io/atomic_file.hpp"

namespace bushel::scenario_running {
namespace {

// The progress line's steps/s and ETA are over this much of the latest wall time [s].
constexpr double progress_window = 300.0;

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  const auto t = static_cast<long>(s + 0.5);
  return t >= 3600 ? fmt::format("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
                   : fmt::format("{}:{:02}", t / 60, t % 60);
}

// The files and folders a run writes in its output folder.
constexpr std::array<const char*, 5> run_outputs = {"summary.json", "timeseries.csv", "timeseries.units.csv",
                                                    "checkpoint.bin", "frames"};

}  // namespace

void clear_output(const RunOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<fs::path> found;
  for (const char* name : run_outputs) {
    if (fs::exists(fs::path(o.out_dir) / name, ec)) found.push_back(fs::path(o.out_dir) / name);
  }
  if (found.empty()) return;
  if (!o.overwrite) {
    throw InputError(fmt::format("the folder holds another run ({}): give another --out, continue it with "
                                 "--restart, or replace it with --overwrite",
                                 found.front().filename().string()))
        .with_key("--out")
        .at(o.out_dir);
  }
  for (const fs::path& p : found) {
    fs::remove_all(p, ec);
    if (ec)
      throw InputError("cannot remove the earlier run's " + p.filename().string() + ": " + ec.message()).at(o.out_dir);
  }
}

void prepare_output(const RunOptions& o) {
  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec) throw InputError("cannot create the output folder: " + ec.message()).with_key(o.out_dir);
}

ThreadPolicy thread_policy(const Scenario& sc, const RunOptions& o) {
  return o.threads > 0 ? ThreadPolicy{.max = o.threads, .adaptive = false} : sc.settings.threads;
}

void SeriesWriter::open(const std::string& out_dir, const Scenario& sc, const std::vector<std::string>& names,
                        const std::vector<std::string>& chosen, bool resume, std::uint64_t& bytes) {
  namespace fs = std::filesystem;
  for (const auto& name : chosen.empty() ? names : chosen) {
    columns_.push_back(static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin()));
  }
  const fs::path series_path = fs::path(out_dir) / "timeseries.csv";
  if (resume) {
    // Rows after the checkpoint were written by the stopped run: they are written again.
    std::error_code ec;
    if (fs::file_size(series_path, ec) < bytes || ec) {
      throw InputError(
          "timeseries.csv is shorter than the checkpoint says (another run's, or cut): the run "
          "cannot be continued here")
          .at(series_path.string());
    }
    fs::resize_file(series_path, bytes, ec);
    if (ec) throw InputError("cannot continue the time series: " + ec.message()).at(series_path.string());
    out_.open(series_path, std::ios::app);
  } else {
    out_.open(series_path);
    out_ << "stage";
    for (const std::size_t c : columns_) out_ << ',' << names[c];
    out_ << '\n';
    out_.flush();
    bytes = static_cast<std::uint64_t>(out_.tellp());
    // The unit of each column as the rows give it (SI; angles in degrees; "-": none).
    std::string units = "column,unit\nstage,-\n";
    for (const std::size_t c : columns_) {
      const units::Dimension d = sc.value_dimension(names[c]);
      units += names[c] + "," + (d == units::dim::dimensionless ? "-" : std::string(result_unit(d))) + "\n";
    }
    io::write_file_atomically((fs::path(out_dir) / "timeseries.units.csv").string(), units);
  }
  if (!out_) throw InputError("cannot write the time series").at(series_path.string());
}

std::uint64_t SeriesWriter::write_row(const std::string& stage, const std::vector<double>& values) {
  out_ << stage;
  for (const std::size_t c : columns_) out_ << ',' << fmt::format("{:.9g}", values[c]);
  out_ << '\n';
  out_.flush();
  return static_cast<std::uint64_t>(out_.tellp());
}

Progress::Progress(const RunOptions& o, std::size_t stages)
    : o_(o), stages_(stages), tty_(o.progress && isatty(fileno(stderr)) != 0), last_line_(Clock::now()) {}

void Progress::stage_entered(std::uint64_t steps) {
  stage_wall0_ = Clock::now();
  recent_steps_ = {};
  recent_steps_.add(0.0, static_cast<double>(steps), progress_window);
}

void Progress::line(const Simulation& sim, const StageSpec& stage, std::size_t index, double t0, double limit) {
  if (!o_.progress) return;
  const auto now = Clock::now();
  const double since = std::chrono::duration<double>(now - last_line_).count();
  if (tty_ ? since < 0.25 : since < o_.progress_interval) return;
  last_line_ = now;
  // The speed over the last progress_window of wall time, not since the stage began: a
  // pour slows as contacts multiply, and a long sitting's average would lag far behind.
  const double w = std::chrono::duration<double>(now - stage_wall0_).count();
  recent_steps_.add(w, static_cast<double>(sim.steps()), progress_window);
  const double steps_per_s = recent_steps_.slope();
  const double eta = steps_per_s > 0.0 ? (limit - (sim.time() - t0)) / (steps_per_s * sim.settings().dt)
                                       : std::numeric_limits<double>::infinity();
  fmt::print(stderr, "{}stage {}/{} {}  t = {:.4f} s  particles {}  {:.0f} steps/s  {}  stage ETA {}{}{}",
             tty_ ? "\r" : "", index + 1, stages_, stage.name, sim.time(), sim.particles().bodies(), steps_per_s,
             sim.threads().describe(), stage.duration ? "" : "<= ", format_duration(eta), tty_ ? "   " : "\n");
}

void Progress::stage_ended(const Simulation& sim, const StageReport& r, std::size_t index) {
  if (!o_.progress) return;
  fmt::print(stderr, "{}stage {}/{} {} ended by {} at t = {:.4f} s ({} steps)\n", tty_ ? "\r" : "", index + 1, stages_,
             r.name, r.ended_by, sim.time(), r.steps);
}

void Progress::failed(const std::string& why) {
  if (o_.progress) fmt::print(stderr, "{}the run failed {}\n", tty_ ? "\n" : "", why);
}

void Progress::interrupted(double time) {
  if (!o_.progress) return;
  fmt::print(stderr, "{}interrupted at t = {:.4f} s: checkpoint written; continue with: bushel run --restart {}\n",
             tty_ ? "\n" : "", time, o_.out_dir);
}

}  // namespace bushel::scenario_running
