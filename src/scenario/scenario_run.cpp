#include "bushel/scenario/scenario_run.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "bushel/core/build_info.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/io/binary_archive.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/scenario/frame_writer.hpp"
#include "bushel/sensors/heap_profile.hpp"
#include "run_checkpoint.hpp"
#include "run_outputs.hpp"
#include "run_results.hpp"
#include "run_state.hpp"
#include "run_warnings.hpp"

namespace bushel {
namespace {

using namespace scenario_running;
using Clock = std::chrono::steady_clock;

// Ctrl-C: the run stops at its next check, writes a checkpoint and returns.
// SIGTERM (what a batch scheduler or `kill` sends) does the same: the signal is kept so that
// the program can exit as a shell expects (128 + signal).
std::atomic<int> interrupt_signal{0};
extern "C" void on_interrupt(int signal) { interrupt_signal.store(signal); }

// Catches SIGINT and SIGTERM for as long as it lives.
class InterruptGuard {
 public:
  InterruptGuard() {
    interrupt_signal.store(0);
    int_ = std::signal(SIGINT, on_interrupt);
    term_ = std::signal(SIGTERM, on_interrupt);
  }
  ~InterruptGuard() {
    std::signal(SIGINT, int_);
    std::signal(SIGTERM, term_);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  void (*int_)(int) = SIG_DFL;
  void (*term_)(int) = SIG_DFL;
};

// The stage machine: each stage's actions, then checks until one of its end conditions is
// met; between checks the steps, and at each check the factories, sinks, flow counts, guards,
// outputs due and checkpoints.
class Runner {
 public:
  Runner(const Scenario& sc, const RunOptions& o) : sc_(sc), o_(o), st_(sc, thread_policy(sc, o)) {}

  // A fresh run; or, with `in`, the rest of the checkpointed run in it.
  RunReport run(const io::SectionTable* in) {
    if (sc_.outputs.frame_interval > 0.0)
      frames_.emplace((std::filesystem::path(o_.out_dir) / "frames").string(), sc_.outputs.frames);
    if (in) {
      load_checkpoint(*in, st_, pos_, frames());
      if (!pos_.failed.empty()) {
        throw InputError("this run failed " + pos_.failed +
                         "; it cannot be continued: correct the scenario and "
                         "start it again (--overwrite)")
            .at(o_.out_dir);
      }
    }
    if (pos_.engines.empty() || pos_.engines.back() != build_description()) pos_.engines.push_back(build_description());
    series_.open(o_.out_dir, sc_, st_.names, sc_.outputs.series, in != nullptr, pos_.series_bytes);
    const InterruptGuard catching;
    return loop();
  }

 private:
  double wall() const { return pos_.wall_before + std::chrono::duration<double>(Clock::now() - wall0_).count(); }
  io::FrameWriter* frames() { return frames_ ? &*frames_ : nullptr; }

  void write_row(const std::string& stage) { pos_.series_bytes = series_.write_row(stage, st_.values()); }

  void checkpoint() {
    save_checkpoint(o_.out_dir, st_, pos_, frames(), wall());
    last_checkpoint_ = Clock::now();
  }

  // The particles created and lost so far, for the lost guard.
  ParticleTally tally() const {
    ParticleTally t{st_.lost.total_count(), 0};
    for (const auto& f : st_.factories) t.created += f.report().total_count;
    return t;
  }

  // The first end condition the stage meets now, or none. `reached` and `stable` locate the
  // stage's values of those conditions.
  std::optional<StageEnd> ended_by(const StageSpec& stage, const RunState::ValueRef& reached,
                                   const RunState::ValueRef& stable) {
    const Simulation& sim = st_.sim;
    const double dt = sim.settings().dt, elapsed = sim.time() - pos_.t0;
    if (stage.duration && elapsed >= *stage.duration - 0.5 * dt) return StageEnd::time;
    if (elapsed >= stage.min_time - 0.5 * dt && elapsed > 0.0) {
      if (stage.kinetic_energy && st_.kinetic_energy_per_particle() < *stage.kinetic_energy)
        return StageEnd::kinetic_energy;
      if (stage.factories_done) {
        bool all = true;
        for (std::size_t f = 0; f < st_.factories.size(); ++f)
          all = all && (!st_.factory_on[f] || st_.factories[f].done());
        if (all) return StageEnd::factories_done;
      }
      if (stage.servo_part) {
        const ServoState& s = sim.part(*stage.servo_part).servo;
        if (s.held && s.held_since >= 0.0 && sim.time() - s.held_since >= stage.servo_hold) return StageEnd::servo_held;
      }
      if (stage.reached) {
        const double v = st_.value(reached);
        if (stage.reached_above ? v >= stage.reached_threshold : v <= stage.reached_threshold) return StageEnd::reached;
      }
      if (stage.stable) {
        SampleWindow& w = pos_.history;
        if (w.time.empty() || w.time.back() < sim.time()) {  // (once per time: a restart checks again)
          w.add(sim.time(), st_.value(stable), stage.stable_window);
        }
        const auto& v = w.value;
        if (w.time.front() <= sim.time() - stage.stable_window + 0.5 * dt) {
          const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
          if (*hi - *lo <= stage.stable_tolerance * std::max(std::abs(*lo), std::abs(*hi))) return StageEnd::stable;
        }
      }
    }
    if (elapsed >= stage.max_time - 0.5 * dt) return StageEnd::max_time;
    return std::nullopt;
  }

  // A stage's actions, once (not again when a restart continues it): its switches and motions.
  void start_stage(const StageSpec& stage) {
    Simulation& sim = st_.sim;
    pos_.t0 = sim.time();
    pos_.steps0 = sim.steps();
    pos_.history = {};
    for (const auto& [f, on] : stage.factories) st_.factory_on[f] = on;
    for (const auto& [k, on] : stage.sinks) st_.sinks[k].enabled = on;
    for (const auto& [p, on] : stage.parts) sim.set_part_enabled(p, on);
    for (const auto& [p, m] : stage.motions) sim.set_motion(p, shifted(m, pos_.t0));
    pos_.stage_started = true;
  }

  // The outputs due now, and a checkpoint (periodic, or asked for by Ctrl-C) between checks,
  // where nothing is half done. True if the run stops here.
  bool outputs_due(const StageSpec& stage, double dt) {
    const Simulation& sim = st_.sim;
    if (sim.time() >= pos_.next_row - 0.5 * dt) {
      write_row(stage.name);
      pos_.next_row += sc_.outputs.series_interval;
    }
    if (frames_ && sim.time() >= pos_.next_frame - 0.5 * dt) {
      frames_->write(sim);
      pos_.next_frame += sc_.outputs.frame_interval;
    }
    at_stop_time_ = sim.time() >= o_.interrupt_at - 0.5 * dt;
    const bool asked = o_.on_check && o_.on_check({stage.name, pos_.stage, sc_.stages.size(), sim.time(),
                                                   sim.particles().bodies(), sim.steps(), wall()});
    const bool stop = interrupt_signal.load() != 0 || at_stop_time_ || asked;
    if (stop || (o_.checkpoint_interval > 0.0 &&
                 std::chrono::duration<double>(Clock::now() - last_checkpoint_).count() >= o_.checkpoint_interval)) {
      checkpoint();
      interrupted_ = stop;
    }
    return interrupted_;
  }

  // Advances to the next check or the end of the stage, and acts at it: the guards, factories,
  // sinks and flow counts. False if a guard stopped the run. Outputs wait for a check (and are
  // written at its time): stopping the steps at their times would move the checks (factories,
  // sinks, stage conditions), so a new column or frame rate would change what is simulated.
  bool step_to_next_check(const StageSpec& stage, double dt, double limit) {
    Simulation& sim = st_.sim;
    const double elapsed = sim.time() - pos_.t0;
    const double span = std::min(sc_.check_interval, limit - elapsed);
    const auto n = static_cast<std::uint64_t>(std::max(1.0, std::round(span / dt)));
    const double before = sim.time();
    sim.step(n);
    const double peak = sim.peak_overlap_ratio();
    pos_.peak_overlap = std::max(pos_.peak_overlap, peak);
    sim.reset_peak_overlap_ratio();
    pos_.particle_steps += static_cast<double>(n) * static_cast<double>(sim.particles().bodies());
    if (const std::string why = check_guards(sc_.guards, pos_.guards, sim, before, peak, tally()); !why.empty()) {
      pos_.failed = fmt::format("at t = {:.6g} s in stage '{}': {}", sim.time(), stage.name, why);
      checkpoint();
      return false;
    }
    for (std::size_t f = 0; f < st_.factories.size(); ++f) {
      if (!st_.factory_on[f]) continue;
      const FactorySpec& spec = st_.factories[f].spec();
      const double active = std::max(0.0, std::min(sim.time(), spec.stop) - std::max(before, spec.start));
      if (active > 0.0) st_.factories[f].run(sim, active);
    }
    apply_sinks(sim, st_.sinks, sc_.domain, st_.lost);
    for (auto& f : st_.flows) f.update(sim.particles(), sim.time());
    return true;
  }

  // The current stage's checks until it ends (what ended it), or the run stops (none).
  std::optional<StageEnd> run_stage(const StageSpec& stage) {
    Simulation& sim = st_.sim;
    if (!pos_.stage_started) start_stage(stage);
    // (set on every entry, a restart's too: the step is the scenario's, not the checkpoint's)
    sim.set_time_step(stage.dt.value_or(sc_.settings.dt));
    const double dt = sim.settings().dt;
    progress_->stage_entered(sim.steps());
    const double limit = stage.duration ? std::min(*stage.duration, stage.max_time) : stage.max_time;
    const RunState::ValueRef reached = stage.reached ? st_.find(*stage.reached) : RunState::ValueRef{};
    const RunState::ValueRef stable = stage.stable ? st_.find(*stage.stable) : RunState::ValueRef{};
    std::optional<StageEnd> end;
    while (!(end = ended_by(stage, reached, stable))) {
      if (outputs_due(stage, dt) || !step_to_next_check(stage, dt, limit)) return std::nullopt;
      progress_->line(sim, stage, pos_.stage, pos_.t0, limit);
    }
    return end;
  }

  // A stage ended: its report (its end values, its heap profiles) and warnings.
  void finish_stage(const StageSpec& stage, StageEnd end) {
    const Simulation& sim = st_.sim;
    StageReport sr{stage.name, std::string(to_string(end)), pos_.t0, sim.time(), sim.steps() - pos_.steps0, {}, {}};
    sr.values = st_.named_values();
    for (const auto& k : sc_.sensors) {
      const auto* heap = k.as<HeapSensorSpec>();
      if (heap == nullptr) continue;
      const HeapProfile h = heap_profile(sim, heap->centre.x, heap->centre.y, heap->outer, heap->rings);
      sr.profiles.push_back({k.name, h.radius, h.height});
    }
    progress_->stage_ended(sim, sr, pos_.stage);
    add_stage_end_warnings(stage, end, sr.steps, sim.settings().dt, st_, pos_.warnings);
    if (pos_.peak_overlap > overlap_warning_ratio) pos_.deep_overlaps.emplace_back(stage.name, pos_.peak_overlap);
    pos_.peak_overlap = 0.0;
    pos_.done.push_back(std::move(sr));
    ++pos_.stage;
    pos_.stage_started = false;
  }

  // The run's end (finished, interrupted or failed): its last row and frame, its report and
  // summary.json.
  RunReport finish_run() {
    const Simulation& sim = st_.sim;
    RunReport report;
    report.interrupted = interrupted_;
    report.at_stop_time = interrupted_ && at_stop_time_;
    report.signal = interrupt_signal.load();
    report.failed = pos_.failed;
    if (!pos_.failed.empty()) {
      progress_->failed(pos_.failed);
      if (frames_) frames_->write(sim);  // (the state that failed, to look at)
    } else if (interrupted_) {
      progress_->interrupted(sim.time());
    } else {
      write_row("end");
      if (frames_) frames_->write(sim);
    }
    report.stages = pos_.done;
    report.steps = sim.steps();
    report.simulated_time = sim.time();
    report.wall_time = wall();
    report.particle_steps = pos_.particle_steps;
    report.warnings = pos_.warnings;
    report.engines = pos_.engines;
    add_run_end_warnings(report, pos_, st_);
    report.summary = build_run_summary(report, st_, o_);
    write_run_summary(report.summary, o_.out_dir);
    return report;
  }

  RunReport loop() {
    wall0_ = last_checkpoint_ = Clock::now();
    progress_.emplace(o_, sc_.stages.size());
    while (pos_.stage < sc_.stages.size() && !interrupted_ && pos_.failed.empty()) {
      const StageSpec& stage = sc_.stages[pos_.stage];
      if (!stage.enabled) {
        ++pos_.stage;
        continue;
      }
      const std::optional<StageEnd> end = run_stage(stage);
      if (!end) break;
      finish_stage(stage, *end);
    }
    return finish_run();
  }

  const Scenario& sc_;
  const RunOptions& o_;
  RunState st_;
  Position pos_;
  std::optional<io::FrameWriter> frames_;
  SeriesWriter series_;
  std::optional<Progress> progress_;
  Clock::time_point wall0_, last_checkpoint_;
  bool interrupted_ = false;   // stopped by Ctrl-C or RunOptions::interrupt_at
  bool at_stop_time_ = false;  // at RunOptions::interrupt_at (at the last check)
};

}  // namespace

RunReport run_scenario(const Scenario& sc, const RunOptions& options) {
  clear_output(options);
  prepare_output(options);
  Runner runner(sc, options);
  return runner.run(nullptr);
}

std::optional<double> surface_shortfall(const StageReport& r, const std::string& sensor) {
  const auto m = std::find_if(r.values.begin(), r.values.end(),
                              [&](const auto& x) { return x.first == sensor + ".surface_margin"; });
  if (m == r.values.end() || m->second >= 0.0) return std::nullopt;
  return -m->second;
}

RunReport resume_scenario(const RunOptions& options) {
  const std::string path = (std::filesystem::path(options.out_dir) / "checkpoint.bin").string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError("no checkpoint to continue from").at(path);
  const std::string bytes = io::read_text_file(path);
  io::BinaryReader in(bytes, path);
  std::optional<io::SectionTable> sections;
  const Scenario sc = read_scenario(read_checkpoint_head(in, path, sections));
  prepare_output(options);
  Runner runner(sc, options);
  return runner.run(&*sections);
}

}  // namespace bushel
