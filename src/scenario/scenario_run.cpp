#include "bushel/scenario/scenario_run.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <csignal>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "bushel/core/build_info.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/core/sample_window.hpp"
#include "bushel/insertion/sink.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/binary_archive.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/io/frame_writer.hpp"
#include "bushel/sensors/heap_profile.hpp"
#include "bushel/sensors/plane_flow.hpp"
#include "bushel/sensors/region_sensor.hpp"
#include "sensor_readings.hpp"

#ifdef BUSHEL_HAVE_OPENMP
#include <omp.h>
#endif

namespace bushel {
namespace {

using Clock = std::chrono::steady_clock;

// Motion times of a stage count from its start.
Motion shifted(Motion m, double t0) {
  for (auto& s : m.segments) s.start += t0, s.end += t0;
  m.servo.start += t0;
  m.servo.end += t0;
  return m;
}

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

  explicit RunState(const Scenario& s) : sc(s), sim(s.settings), factory_on(s.factory_enabled) {
    for (const auto& t : sc.types) {
      sim.particles().add_type(t);
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

  double kinetic_energy_per_particle() const {
    const auto n = sim.particles().bodies();
    return n > 0 ? sim.particles().kinetic_energy() / static_cast<double>(n) : 0.0;
  }

  // The global values, in the order of global_value_names().
  std::vector<double> global_values() const {
    const ParticleSystem& ps = sim.particles();
    std::vector<double> v;
    v.reserve(names.size());
    double potential = 0.0, created = 0.0, removed = 0.0;
    for (std::size_t b = 0; b < ps.bodies(); ++b) potential -= ps.mass[b] * dot(sc.settings.gravity, ps.position[b]);
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
  ValueRef find(const std::string& name) const {
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

  // One value, reading only what it needs.
  double value(const ValueRef& ref) const {
    if (ref.column == ValueRef::none) return std::numeric_limits<double>::quiet_NaN();
    if (ref.sensor == ValueRef::none) return global_values()[ref.column];
    std::vector<double> v;
    append_sensor(ref.sensor, v);
    return v[ref.column];
  }
};

// The scenario as resolved (overrides applied, parameters substituted), as YAML text.
std::string echo_text(const ScenarioDocument& doc) {
  YAML::Emitter echo;
  echo << doc.root;
  return echo.c_str();
}

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  const auto t = static_cast<long>(s + 0.5);
  return t >= 3600 ? fmt::format("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
                   : fmt::format("{}:{:02}", t / 60, t % 60);
}

// FNV-1a over the bits of the bodies' state: equal hashes, equal runs (restart, threads).
std::uint64_t state_hash(const ParticleSystem& ps) {
  std::uint64_t h = 1469598103934665603ULL;
  auto mix = [&](const auto& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    for (std::size_t i = 0; i < v.size() * sizeof(v[0]); ++i) h = (h ^ p[i]) * 1099511628211ULL;
  };
  mix(ps.body_id);
  mix(ps.position);
  mix(ps.velocity);
  mix(ps.angular_momentum);
  mix(ps.orientation);
  return h;
}

// "bushel checkpoint N", N = Simulation::checkpoint_format.
std::string checkpoint_magic(int format) { return "bushel checkpoint " + std::to_string(format); }

// A run continued from a checkpoint by another build than the one that wrote it: its results
// mix the two (a changed contact law, say), which the summary must say.
std::string mixed_engines_warning(const std::vector<std::string>& engines) {
  std::string list;
  for (std::size_t k = 0; k < engines.size(); ++k) list += (k == 0 ? "" : ", then ") + engines[k];
  return "the run was continued from a checkpoint by another engine build, so its results mix builds: " + list;
}

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

// The members of a Position, then of a Sink, that a checkpoint holds, in file order: one list
// for writing and reading (P is Position or const Position; the rest of the position has
// its own format).
template <class P, class F>
requires std::is_same_v<std::remove_const_t<P>, Position>
void each_checkpointed(P& p, F&& f) {
  f(p.stage);
  f(p.stage_started);
  f(p.t0);
  f(p.steps0);
  f(p.history.time);
  f(p.history.value);
  f(p.next_row);
  f(p.next_frame);
  f(p.particle_steps);
}
template <class K, class F>
requires std::is_same_v<std::remove_const_t<K>, Sink>
void each_checkpointed(K& k, F&& f) {
  f(k.enabled);
  f(k.count);
  f(k.mass);
}

// physics.md section 3: warn when the largest overlap exceeds a few percent of the radius.
// Deeper than this the contacts are too soft for the impacts or loads of the stage, and what
// it measures (a density under load above all) includes kernels interpenetrating.
constexpr double overlap_warning_ratio = 0.05;

// A stage that waits for the particles to come to rest (a kinetic_energy condition) should end
// near equilibrium: about 1e-4 (wheat.md), and 0.001 to 0.02 in the calibration cups. Explicit
// integration of strong tangential damping without its bound (simulation.tangential_damping_limit
// off; restitution 0.05 at 0.2 of the Rayleigh step: 0.36) leaves the packing jittering, and it
// compacts (docs/scenarios.md): 0.26 to 0.51 in the cases measured. A stage that ends the
// moment the kinetic energy falls catches a small packing that has just come to rest at up to
// 0.14 (the unit tests' 300-sphere cup, 16 runs; 2e-4 0.2 s later), so the threshold lies
// between the two.
constexpr double jitter_unbalanced_force = 0.2;

// The progress line's steps/s and ETA are over this much of the latest wall time [s].
constexpr double progress_window = 300.0;

// The value `value` at the end of the stage `r`, or 0 if it is not among its values.
double end_value(const StageReport& r, const std::string& value) {
  for (const auto& [name, v] : r.values)
    if (name == value) return v;
  return 0.0;
}

// The largest overlap over the smaller radius at the end of the finished stage `name`, or 0.
double end_overlap(const std::vector<StageReport>& done, const std::string& name) {
  for (const StageReport& r : done)
    if (r.name == name) return end_value(r, "max_overlap_ratio");
  return 0.0;
}

// The warning for `count` particles of `mass` [kg] that left the domain, with the stages they
// left in (from the rise of lost_count over each finished stage), so that a reader can tell
// kernels lost before a measurement from those lost after it.
std::string lost_warning(std::size_t count, double mass, const std::vector<StageReport>& done) {
  std::vector<std::pair<std::string, std::size_t>> in;  // stage, particles lost in it
  std::size_t before = 0;
  for (const StageReport& r : done) {
    const auto after = static_cast<std::size_t>(end_value(r, "lost_count"));
    if (after > before) in.emplace_back(r.name, after - before);
    before = std::max(before, after);
  }
  std::string where;  // none when the stages' counts do not add up to it (not all recorded)
  if (before == count && in.size() == 1) {
    where = fmt::format(", {}in stage '{}'", count == 1 ? "" : "all ", in.front().first);
  } else if (before == count) {
    where = ":";
    for (std::size_t k = 0; k < in.size(); ++k)
      where += fmt::format("{} {} in '{}'", k == 0 ? "" : ",", in[k].second, in[k].first);
  }
  return fmt::format("{} particle{} ({:.3g} g) left the domain{}", count, count == 1 ? "" : "s", 1e3 * mass, where);
}

// One warning for the stages whose deepest overlap passed overlap_warning_ratio. It says
// whether the overlap was still that deep at their ends: a stream's impacts pass it for a
// moment (the README's cup: 8.3 % in the fill, 0.5 % at the end of the settling), while a
// packing whose kernels sink into each other under load ends on it, and what it measures
// includes them interpenetrating.
std::string overlap_warning(const std::vector<std::pair<std::string, double>>& stages,
                            const std::vector<StageReport>& done) {
  const auto deepest =
      std::max_element(stages.begin(), stages.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  auto named = [](const std::string& stage, double ratio) {
    return fmt::format("'{}' ({:.1f} %)", stage, 100.0 * ratio);
  };
  const bool one = stages.size() == 1;
  const std::string where =
      one ? "stage " + named(stages.front().first, stages.front().second)
          : fmt::format("{} stages, from {} to {}, at most {:.1f} % in '{}'", stages.size(),
                        named(stages.front().first, stages.front().second),
                        named(stages.back().first, stages.back().second), 100.0 * deepest->second, deepest->first);
  std::vector<std::string> still;  // the stages that ended that deep
  double end_max = -1.0;
  std::string end_max_stage;
  for (const auto& [stage, peak] : stages) {
    const double end = end_overlap(done, stage);
    if (end > overlap_warning_ratio) still.push_back(named(stage, end));
    if (end > end_max) end_max = end, end_max_stage = stage;
  }
  const std::string head = fmt::format(
      "the largest overlap passed {:.0f} % of the smaller radius in {}: the contacts "
      "are soft for these impacts or loads",
      100.0 * overlap_warning_ratio, where);
  const std::string shallower = "(a stiffer material, or a gentler drop, makes the impacts shallower)";
  if (still.empty() && one) {
    return fmt::format(
        "{}, but at the stage's end it was {:.1f} %, so the packing it ends on is not interpenetrating {}", head,
        100.0 * end_max, shallower);
  }
  if (still.empty()) {
    return fmt::format(
        "{}, but at the end of each it was under {:.0f} % (at most {:.1f} %, at the end of '{}'), so the packings "
        "they end on are not interpenetrating {}",
        head, 100.0 * overlap_warning_ratio, 100.0 * end_max, end_max_stage, shallower);
  }
  return fmt::format(
      "{}, and at the end of {} it still was: what {} includes kernels interpenetrating (a stiffer "
      "material, or a gentler load or drop)",
      head, fmt::join(still, ", "), still.size() == 1 ? "that stage measures" : "those stages measure");
}

void put(io::BinaryWriter& out, const StageReport& r) {
  out.put(r.name);
  out.put(r.ended_by);
  out.put(r.start);
  out.put(r.end);
  out.put(r.steps);
  out.put(static_cast<std::uint64_t>(r.values.size()));
  for (const auto& [k, v] : r.values) out.put(k), out.put(v);
  out.put(static_cast<std::uint64_t>(r.profiles.size()));
  for (const auto& p : r.profiles) out.put(p.sensor), out.put(p.radius), out.put(p.height);
}

StageReport get_report(io::BinaryReader& in) {
  StageReport r;
  in.get(r.name);
  in.get(r.ended_by);
  in.get(r.start);
  in.get(r.end);
  in.get(r.steps);
  const auto n = in.get_count(16);
  for (std::uint64_t k = 0; k < n; ++k) {
    auto name = in.get<std::string>();
    r.values.emplace_back(std::move(name), in.get<double>());
  }
  r.profiles.resize(in.get_count(24));
  for (auto& p : r.profiles) in.get(p.sensor), in.get(p.radius), in.get(p.height);
  return r;
}

class Runner {
 public:
  Runner(const Scenario& sc, const RunOptions& o) : sc_(sc), o_(o), st_(sc) {}

  // A fresh run; or, with `in`, the rest of the checkpointed run in it.
  RunReport run(io::BinaryReader* in) {
    namespace fs = std::filesystem;
    const fs::path dir(o_.out_dir);
    if (sc_.outputs.frame_interval > 0.0) frames_.emplace((dir / "frames").string());
    if (in) {
      load(*in);
      if (!pos_.failed.empty()) {
        throw InputError("this run failed " + pos_.failed +
                         "; it cannot be continued: correct the scenario and "
                         "start it again (--overwrite)")
            .at(o_.out_dir);
      }
    }
    if (pos_.engines.empty() || pos_.engines.back() != build_description()) pos_.engines.push_back(build_description());
    for (const auto& name : sc_.outputs.series.empty() ? st_.names : sc_.outputs.series) {
      columns_.push_back(
          static_cast<std::size_t>(std::find(st_.names.begin(), st_.names.end(), name) - st_.names.begin()));
    }
    const fs::path series_path = dir / "timeseries.csv";
    if (in) {
      // Rows after the checkpoint were written by the stopped run: they are written again.
      std::error_code ec;
      if (fs::file_size(series_path, ec) < pos_.series_bytes || ec) {
        throw InputError(
            "timeseries.csv is shorter than the checkpoint says (another run's, or cut): the run "
            "cannot be continued here")
            .at(series_path.string());
      }
      fs::resize_file(series_path, pos_.series_bytes, ec);
      if (ec) throw InputError("cannot continue the time series: " + ec.message()).at(series_path.string());
      series_.open(series_path, std::ios::app);
    } else {
      series_.open(series_path);
      series_ << "stage";
      for (const std::size_t c : columns_) series_ << ',' << st_.names[c];
      series_ << '\n';
      series_.flush();
      pos_.series_bytes = static_cast<std::uint64_t>(series_.tellp());
    }
    if (!series_) throw InputError("cannot write the time series").at(series_path.string());
    const InterruptGuard catching;
    return loop();
  }

 private:
  double wall() const { return pos_.wall_before + std::chrono::duration<double>(Clock::now() - wall0_).count(); }

  void write_row(const std::string& stage) {
    const auto v = st_.values();
    series_ << stage;
    for (const std::size_t c : columns_) series_ << ',' << fmt::format("{:.9g}", v[c]);
    series_ << '\n';
    series_.flush();
    pos_.series_bytes = static_cast<std::uint64_t>(series_.tellp());
  }

  // The checkpoint: its magic line, then sections with checksums (binary_archive.hpp): the
  // build that wrote it, the scenario as resolved, where the run stands, the engine's state.
  void save_checkpoint() {
    io::BinaryWriter out, build, scenario, run, engine;
    out.put(checkpoint_magic(Simulation::checkpoint_format));
    build.put(build_description());
    out.put_section("build", build);
    scenario.put(sc_.document.file);
    scenario.put(echo_text(sc_.document));
    scenario.put(static_cast<std::uint64_t>(sc_.document.overrides.size()));
    for (const auto& ov : sc_.document.overrides) scenario.put(ov.path), scenario.put(ov.value);
    scenario.put(static_cast<std::uint64_t>(sc_.document.parameters.size()));
    for (const auto& [k, v] : sc_.document.parameters) scenario.put(k), scenario.put(v);
    each_checkpointed(pos_, [&](const auto& m) { run.put(m); });
    run.put(wall());
    run.put(pos_.series_bytes);
    run.put(static_cast<std::uint64_t>(pos_.done.size()));
    for (const auto& r : pos_.done) put(run, r);
    run.put(static_cast<std::uint64_t>(pos_.warnings.size()));
    for (const auto& w : pos_.warnings) run.put(w);
    run.put(st_.factory_on);
    for (const auto& f : st_.factories) f.save(run);
    for (const Sink* k : sinks_and_lost()) each_checkpointed(*k, [&](const auto& m) { run.put(m); });
    for (const auto& f : st_.flows) f.save(run);
    if (frames_) frames_->save(run);
    run.put(pos_.peak_overlap);
    run.put(static_cast<std::uint64_t>(pos_.deep_overlaps.size()));
    for (const auto& [name, peak] : pos_.deep_overlaps) run.put(name), run.put(peak);
    run.put(static_cast<std::uint64_t>(pos_.engines.size()));
    for (const auto& e : pos_.engines) run.put(e);
    pos_.guards.save(run);
    run.put(pos_.failed);
    st_.sim.save_state(engine);
    st_.sim.save_force_sums(engine);
    st_.sim.save_skin_clock(engine);
    out.put_section("scenario", scenario);
    out.put_section("run", run);
    out.put_section("engine", engine);
    io::write_file_atomically((std::filesystem::path(o_.out_dir) / "checkpoint.bin").string(), out.bytes());
    last_checkpoint_ = Clock::now();
  }

  // The run and engine sections (the header and the scenario were read by resume_scenario).
  void load(io::BinaryReader& file) {
    io::BinaryReader in = file.section("run");
    io::BinaryReader engine = file.section("engine");
    if (!file.done()) file.damaged("data after its last section");
    each_checkpointed(pos_, [&](auto& m) { in.get(m); });
    in.get(pos_.wall_before);
    in.get(pos_.series_bytes);
    const auto n_done = in.get_count(8);
    for (std::uint64_t k = 0; k < n_done; ++k) pos_.done.push_back(get_report(in));
    const auto n_warn = in.get_count(8);
    for (std::uint64_t k = 0; k < n_warn; ++k) pos_.warnings.push_back(in.get<std::string>());
    in.get(st_.factory_on);
    if (st_.factory_on.size() != st_.factories.size() || pos_.stage > sc_.stages.size()) {
      in.damaged("it does not match its scenario");
    }
    for (auto& f : st_.factories) f.load(in);
    for (Sink* k : sinks_and_lost()) each_checkpointed(*k, [&](auto& m) { in.get(m); });
    for (auto& f : st_.flows) f.load(in);
    if (frames_) frames_->load(in);
    in.get(pos_.peak_overlap);
    pos_.deep_overlaps.resize(in.get_count(16));
    for (auto& [name, peak] : pos_.deep_overlaps) in.get(name), in.get(peak);
    pos_.engines.resize(in.get_count(8));
    for (auto& e : pos_.engines) in.get(e);
    pos_.guards.load(in);
    in.get(pos_.failed);
    if (!in.done()) in.damaged("unexpected data at the end of section 'run'");
    st_.sim.load_state(engine);
    st_.sim.load_force_sums(engine);
    st_.sim.load_skin_clock(engine);
    if (!engine.done()) engine.damaged("unexpected data at the end of section 'engine'");
  }

  // The particles created and lost so far, for the lost guard.
  ParticleTally tally() const {
    ParticleTally t{st_.lost.total_count(), 0};
    for (const auto& f : st_.factories) t.created += f.report().total_count;
    return t;
  }

  std::vector<Sink*> sinks_and_lost() {
    std::vector<Sink*> all{&st_.lost};
    for (Sink& k : st_.sinks) all.push_back(&k);
    return all;
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

  void progress_line(const StageSpec& stage, double limit) {
    if (!o_.progress) return;
    const auto now = Clock::now();
    const double since = std::chrono::duration<double>(now - last_line_).count();
    if (tty_ ? since < 0.25 : since < o_.progress_interval) return;
    last_line_ = now;
    const Simulation& sim = st_.sim;
    // The speed over the last progress_window of wall time, not since the stage began: a
    // pour slows as contacts multiply, and a long sitting's average would lag far behind.
    const double w = std::chrono::duration<double>(now - stage_wall0_).count();
    recent_steps_.add(w, static_cast<double>(sim.steps()), progress_window);
    const double steps_per_s = recent_steps_.slope();
    const double eta = steps_per_s > 0.0 ? (limit - (sim.time() - pos_.t0)) / (steps_per_s * sim.settings().dt)
                                         : std::numeric_limits<double>::infinity();
    fmt::print(stderr, "{}stage {}/{} {}  t = {:.4f} s  particles {}  {:.0f} steps/s  stage ETA {}{}{}",
               tty_ ? "\r" : "", pos_.stage + 1, sc_.stages.size(), stage.name, sim.time(), sim.particles().bodies(),
               steps_per_s, stage.duration ? "" : "<= ", format_duration(eta), tty_ ? "   " : "\n");
  }

  RunReport loop() {
    Simulation& sim = st_.sim;
    wall0_ = last_line_ = last_checkpoint_ = Clock::now();
    tty_ = o_.progress && isatty(fileno(stderr)) != 0;
    bool interrupted = false, at_stop_time = false;
    while (pos_.stage < sc_.stages.size() && !interrupted && pos_.failed.empty()) {
      const StageSpec& stage = sc_.stages[pos_.stage];
      if (!stage.enabled) {
        ++pos_.stage;
        continue;
      }
      if (!pos_.stage_started) {
        pos_.t0 = sim.time();
        pos_.steps0 = sim.steps();
        pos_.history = {};
        for (const auto& [f, on] : stage.factories) st_.factory_on[f] = on;
        for (const auto& [k, on] : stage.sinks) st_.sinks[k].enabled = on;
        for (const auto& [p, on] : stage.parts) sim.set_part_enabled(p, on);
        for (const auto& [p, m] : stage.motions) sim.set_motion(p, shifted(m, pos_.t0));
        pos_.stage_started = true;
      }
      // (set on every entry, a restart's too: the step is the scenario's, not the checkpoint's)
      sim.set_time_step(stage.dt.value_or(sc_.settings.dt));
      const double dt = sim.settings().dt;
      stage_wall0_ = Clock::now();
      recent_steps_ = {};
      recent_steps_.add(0.0, static_cast<double>(sim.steps()), progress_window);
      const double limit = stage.duration ? std::min(*stage.duration, stage.max_time) : stage.max_time;
      const RunState::ValueRef reached = stage.reached ? st_.find(*stage.reached) : RunState::ValueRef{};
      const RunState::ValueRef stable = stage.stable ? st_.find(*stage.stable) : RunState::ValueRef{};
      std::optional<StageEnd> end;
      while (!(end = ended_by(stage, reached, stable))) {
        // outputs due now
        if (sim.time() >= pos_.next_row - 0.5 * dt) {
          write_row(stage.name);
          pos_.next_row += sc_.outputs.series_interval;
        }
        if (frames_ && sim.time() >= pos_.next_frame - 0.5 * dt) {
          frames_->write(sim);
          pos_.next_frame += sc_.outputs.frame_interval;
        }
        // a checkpoint (periodic, or asked for by Ctrl-C) between checks, where nothing is half done
        at_stop_time = sim.time() >= o_.interrupt_at - 0.5 * dt;
        const bool stop = interrupt_signal.load() != 0 || at_stop_time;
        if (stop ||
            (o_.checkpoint_interval > 0.0 &&
             std::chrono::duration<double>(Clock::now() - last_checkpoint_).count() >= o_.checkpoint_interval)) {
          save_checkpoint();
          if (stop) {
            interrupted = true;
            break;
          }
        }
        // advance to the next check or the end of the stage. Outputs wait for a check (and
        // are written at its time): stopping the steps at their times would move the checks
        // (factories, sinks, stage conditions), so a new column or frame rate would change
        // what is simulated.
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
          save_checkpoint();
          break;
        }
        for (std::size_t f = 0; f < st_.factories.size(); ++f) {
          if (!st_.factory_on[f]) continue;
          const FactorySpec& spec = st_.factories[f].spec();
          const double active = std::max(0.0, std::min(sim.time(), spec.stop) - std::max(before, spec.start));
          if (active > 0.0) st_.factories[f].run(sim, active);
        }
        apply_sinks(sim, st_.sinks, sc_.domain, st_.lost);
        for (auto& f : st_.flows) f.update(sim.particles(), sim.time());
        progress_line(stage, limit);
      }
      if (interrupted || !pos_.failed.empty()) break;
      StageReport sr{stage.name, std::string(to_string(*end)), pos_.t0, sim.time(), sim.steps() - pos_.steps0, {}, {}};
      sr.values = st_.named_values();
      for (const auto& k : sc_.sensors) {
        const auto* heap = k.as<HeapSensorSpec>();
        if (heap == nullptr) continue;
        const HeapProfile h = heap_profile(sim, heap->centre.x, heap->centre.y, heap->outer, heap->rings);
        sr.profiles.push_back({k.name, h.radius, h.height});
      }
      if (o_.progress) {
        fmt::print(stderr, "{}stage {}/{} {} ended by {} at t = {:.4f} s ({} steps)\n", tty_ ? "\r" : "",
                   pos_.stage + 1, sc_.stages.size(), stage.name, sr.ended_by, sim.time(), sr.steps);
      }
      if (*end == StageEnd::max_time &&
          (stage.kinetic_energy || stage.factories_done || stage.servo_part || stage.reached || stage.stable)) {
        pos_.warnings.push_back(
            fmt::format("stage '{}' ended at its time limit before its condition was met", stage.name));
      }
      const double unbalanced = sim.unbalanced_force_ratio();
      // (ended at its first check, far from rest: particles made at rest, all at once, before)
      const bool at_first_check = *end == StageEnd::kinetic_energy &&
                                  sr.steps <= static_cast<std::uint64_t>(std::round(sc_.check_interval / dt));
      if (at_first_check && unbalanced > jitter_unbalanced_force) {
        pos_.warnings.push_back(fmt::format(
            "stage '{}' ended at its first check with the kinetic energy already below its limit, though the "
            "particles are not at rest (unbalanced force ratio {:.2g}): they had not started to move (made at rest, "
            "all at once?), so they have not settled; give the stage a min_time",
            stage.name, unbalanced));
      } else if (stage.kinetic_energy && unbalanced > jitter_unbalanced_force) {
        pos_.warnings.push_back(fmt::format(
            "stage '{}' ended with the packing not at rest (unbalanced force ratio {:.2g}, above {:g}): either it "
            "ended before the packing settled (a longer min_time), or the particles jitter, which compacts a "
            "packing: a smaller time step, and simulation.tangential_damping_limit on (docs/scenarios.md)",
            stage.name, unbalanced, jitter_unbalanced_force));
      }
      if (pos_.peak_overlap > overlap_warning_ratio) pos_.deep_overlaps.emplace_back(stage.name, pos_.peak_overlap);
      pos_.peak_overlap = 0.0;
      pos_.done.push_back(std::move(sr));
      ++pos_.stage;
      pos_.stage_started = false;
    }
    RunReport report;
    report.interrupted = interrupted;
    report.at_stop_time = interrupted && at_stop_time;
    report.signal = interrupt_signal.load();
    report.failed = pos_.failed;
    if (!pos_.failed.empty()) {
      if (o_.progress) fmt::print(stderr, "{}the run failed {}\n", tty_ ? "\n" : "", pos_.failed);
      if (frames_) frames_->write(sim);  // (the state that failed, to look at)
    } else if (interrupted) {
      if (o_.progress) {
        fmt::print(stderr,
                   "{}interrupted at t = {:.4f} s: checkpoint written; continue with: bushel run --restart {}\n",
                   tty_ ? "\n" : "", sim.time(), o_.out_dir);
      }
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
    if (report.engines.size() > 1) report.warnings.push_back(mixed_engines_warning(report.engines));
    if (!pos_.deep_overlaps.empty()) report.warnings.push_back(overlap_warning(pos_.deep_overlaps, pos_.done));
    if (!interrupted && pos_.failed.empty()) {
      for (const auto& f : st_.factories) {
        if (f.done()) continue;
        const double made =
            f.spec().total_by_mass ? f.report().total_mass : static_cast<double>(f.report().total_count);
        report.warnings.push_back(fmt::format("factory '{}' created {:.4g} of its total {:.4g}{}", f.spec().name, made,
                                              f.spec().total, f.spec().total_by_mass ? " kg" : " particles"));
      }
      if (st_.lost.total_count() > 0)
        report.warnings.push_back(lost_warning(st_.lost.total_count(), st_.lost.total_mass(), report.stages));
    }
    report.summary = summary(report);
    write_run_summary(report.summary, o_.out_dir);
    return report;
  }

  // The scenario's results from the stages' end values (SI, angles in degrees): not computed
  // for one whose stages have not run (an interrupted run), are skipped, or that cannot be
  // computed (a warning, unless a stage it names is skipped or the run was interrupted).
  std::vector<RunResult> results(const RunReport& report, std::vector<std::string>& warnings) {
    std::vector<RunResult> out;
    for (const ResultSpec& r : sc_.results) {
      bool skipped = false;  // it names a stage with enabled: false
      std::string not_full;  // why a density it uses counts empty space
      try {
        const units::Quantity q = evaluate_result(r, sc_, [&](const std::string& stage, const std::string& value) {
          const auto s = std::find_if(report.stages.begin(), report.stages.end(),
                                      [&](const StageReport& x) { return x.name == stage; });
          if (s == report.stages.end()) {
            const StageSpec* spec = stage_spec(stage);
            skipped = spec != nullptr && !spec->enabled;
            throw InputError("stage '" + stage + "' has not run");
          }
          if (value == "start") return s->start;
          if (value == "end") return s->end;
          if (value == "duration") return s->end - s->start;
          if (not_full.empty()) not_full = not_full_note(*s, value);
          const auto v =
              std::find_if(s->values.begin(), s->values.end(), [&](const auto& x) { return x.first == value; });
          return v->second;  // (names were checked by read_scenario)
        });
        const double v = result_value(q);
        out.push_back({r.name, std::isfinite(v) ? std::optional(v) : std::nullopt,
                       std::string(result_unit(q.dimension)), not_full});
        if (!not_full.empty()) warnings.push_back(fmt::format("result '{}' means little: {}", r.name, not_full));
        if (o_.progress && !report.interrupted) {
          fmt::print(stderr, "  {} = {:.6g}{}{}{}\n", r.name, result_value(q),
                     q.dimension == units::dim::dimensionless ? "" : " ", result_unit(q.dimension),
                     not_full.empty() ? "" : "  (NOT FULL: see the warning)");
        }
      } catch (const InputError& e) {
        out.push_back({r.name, std::nullopt, "", "", false});
        if (!report.interrupted && !skipped) warnings.push_back("result '" + r.name + "': " + e.problem());
      }
    }
    return out;
  }

  // For a density of a region sensor at the end of stage `r` ("cup.bulk_density"): what
  // makes it meaningless when the region was not full then (region_sensor.hpp), else "".
  static std::string not_full_note(const StageReport& r, const std::string& value) {
    const std::size_t dot = value.rfind('.');
    if (dot == std::string::npos) return "";
    const std::string sensor = value.substr(0, dot), what = value.substr(dot + 1);
    if (what != "bulk_density" && what != "bulk_density_exact" && what != "packing_fraction") return "";
    const std::optional<double> below = surface_shortfall(r, sensor);
    if (!below) return "";
    return fmt::format(
        "region sensor '{}' was not full at the end of stage '{}': the grain surface's lowest "
        "point lay {:.1f} mm below its top, so its {} counts empty space (a lower sensor, or more "
        "grain)",
        sensor, r.name, 1e3 * *below, what);
  }

  // The stage of this name (names are unique), or null.
  const StageSpec* stage_spec(const std::string& name) const {
    const auto s =
        std::find_if(sc_.stages.begin(), sc_.stages.end(), [&](const StageSpec& x) { return x.name == name; });
    return s != sc_.stages.end() ? &*s : nullptr;
  }

  // The time step a stage ran with [s].
  double stage_dt(const std::string& name) const {
    const StageSpec* s = stage_spec(name);
    return s != nullptr && s->dt ? *s->dt : sc_.settings.dt;
  }

  static FactorySummary factory_summary(const Factory& f, const std::vector<std::string>& type_names) {
    FactorySummary out{f.spec().name, f.spec().fractions_by_mass, f.report().total_count, f.report().total_mass, {},
                       f.done()};
    const auto achieved = f.achieved_fractions();
    for (std::size_t k = 0; k < f.spec().types.size(); ++k) {
      out.types.push_back(
          {type_names[f.spec().types[k]], f.report().count[k], f.report().mass[k], achieved[k], f.spec().fractions[k]});
    }
    return out;
  }

  static SinkSummary sink_summary(const Sink& k, const std::vector<std::string>& type_names) {
    SinkSummary out{k.name, k.total_count(), k.total_mass(), {}};
    for (std::size_t t = 0; t < k.count.size(); ++t) out.types.push_back({type_names[t], k.count[t], k.mass[t]});
    return out;
  }

  // What summary.json holds: the report, the scenario's results (printed as they are
  // computed), what the factories created and the sinks removed, the final values.
  RunSummary summary(const RunReport& report) {
    namespace fs = std::filesystem;
    RunSummary s;
    s.directory = o_.out_dir;
    s.file = (fs::path(o_.out_dir) / "summary.json").string();
    s.scenario = fs::absolute(sc_.document.file).string();
    s.engine_version = build_info().version;
    s.engine_commit = build_info().commit;
    s.engine_dirty = build_info().dirty;
    s.engines = report.engines;
    for (const auto& ov : sc_.document.overrides) s.overrides.push_back(ov.path + "=" + ov.value);
    s.parameters.assign(sc_.document.parameters.begin(), sc_.document.parameters.end());
    s.echo = echo_text(sc_.document);
    s.interrupted = report.interrupted;
    s.failed = report.failed;
    s.dt = sc_.settings.dt;
    s.rayleigh_step = sc_.rayleigh_step;
    s.steps = report.steps;
    s.simulated_time = report.simulated_time;
    s.wall_time = report.wall_time;
    s.particle_steps_per_s = report.wall_time > 0.0 ? report.particle_steps / report.wall_time : 0.0;
    s.stages = report.stages;
    for (StageReport& st : s.stages) st.dt = stage_dt(st.name);
    s.warnings = report.warnings;
    s.results = results(report, s.warnings);
    for (const auto& f : st_.factories) s.factories.push_back(factory_summary(f, st_.type_names));
    for (const auto& k : st_.sinks) s.sinks.push_back(sink_summary(k, st_.type_names));
    s.lost = sink_summary(st_.lost, st_.type_names);
    s.final_values = st_.named_values();
    s.final_state_hash = fmt::format("{:016x}", state_hash(st_.sim.particles()));
    return s;
  }

  const Scenario& sc_;
  const RunOptions& o_;
  RunState st_;
  Position pos_;
  std::optional<io::FrameWriter> frames_;
  std::vector<std::size_t> columns_;
  std::ofstream series_;
  Clock::time_point wall0_, last_line_, last_checkpoint_, stage_wall0_;
  SampleWindow recent_steps_;  // (wall s since the stage's start in this sitting, step count)
  bool tty_ = false;
};

// The files and folders a run writes in its output folder.
constexpr std::array<const char*, 4> run_outputs = {"summary.json", "timeseries.csv", "checkpoint.bin", "frames"};

// A fresh run's output folder: created, or refused if it holds another run's outputs unless
// the run may replace them, which are then removed first (so that no old frame or row is
// left beside the new ones, and a kill cannot leave two runs mixed).
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

void prepare_output(const RunOptions& o, int scenario_threads) {
  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec) throw InputError("cannot create the output folder: " + ec.message()).with_key(o.out_dir);
#ifdef BUSHEL_HAVE_OPENMP
  const int threads = o.threads > 0 ? o.threads : scenario_threads;
  if (threads > 0) omp_set_num_threads(threads);
#else
  (void)scenario_threads;
#endif
}

}  // namespace

RunReport run_scenario(const Scenario& sc, const RunOptions& options) {
  clear_output(options);
  prepare_output(options, sc.threads);
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
  const std::string magic = checkpoint_magic(Simulation::checkpoint_format);
  std::string found;
  try {
    found = in.get<std::string>();
  } catch (const InputError&) {  // (too short for even the magic line)
  }
  if (!found.starts_with("bushel checkpoint ")) throw InputError("not a bushel checkpoint").at(path);
  const auto writer = in.section("build").get<std::string>();
  if (found != magic) {
    throw InputError(fmt::format("a checkpoint of format {}, written by bushel {}; this build ({}) reads format {}: "
                                 "continue it with the build that wrote it, or start the run again",
                                 found.substr(magic.size() - 1), writer, build_description(),
                                 Simulation::checkpoint_format))
        .at(path);
  }
  // The scenario as it was resolved (overrides applied, parameters substituted), read again
  // as if from its file, so that relative paths (meshes, templates) still resolve.
  io::BinaryReader head = in.section("scenario");
  const auto file = head.get<std::string>();
  const auto text = head.get<std::string>();
  std::vector<Override> overrides(head.get_count(16));
  for (auto& ov : overrides) head.get(ov.path), head.get(ov.value);
  std::map<std::string, std::string> parameters;
  const auto n_parameters = head.get_count(16);
  for (std::uint64_t k = 0; k < n_parameters; ++k) {
    auto name = head.get<std::string>();
    parameters[name] = head.get<std::string>();
  }
  if (!head.done()) head.damaged("unexpected data at the end of section 'scenario'");
  ScenarioDocument doc = parse_scenario_document(text, file);
  doc.overrides = std::move(overrides);
  doc.parameters = std::move(parameters);
  const Scenario sc = read_scenario(std::move(doc));
  prepare_output(options, sc.threads);
  Runner runner(sc, options);
  return runner.run(&in);
}

}  // namespace bushel
