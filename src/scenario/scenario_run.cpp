#include "bushel/scenario/scenario_run.hpp"

#include <unistd.h>

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
#include <nlohmann/json.hpp>

#include "bushel/core/input_error.hpp"
#include "bushel/insertion/sink.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/frame_writer.hpp"
#include "bushel/sensors/heap_profile.hpp"
#include "bushel/sensors/region_sensor.hpp"

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
  std::vector<std::string> type_names, names;

  explicit RunState(const Scenario& s) : sc(s), sim(s.settings), factory_on(s.factory_enabled) {
    for (const auto& t : sc.types) {
      sim.particles().add_type(t);
      type_names.push_back(t.name);
    }
    for (const auto& p : sc.parts) sim.add_part(p);
    for (const auto& f : sc.factories) factories.emplace_back(f, sim);
    for (const auto& k : sc.sinks) sinks.push_back({k.name, k.region, k.enabled, {}, {}});
    names = sc.value_names();
  }

  double kinetic_energy_per_particle() const {
    const auto n = sim.particles().bodies();
    return n > 0 ? sim.particles().kinetic_energy() / static_cast<double>(n) : 0.0;
  }

  // Every value, in the order of `names`.
  std::vector<double> values() const {
    const ParticleSystem& ps = sim.particles();
    std::vector<double> v;
    v.reserve(names.size());
    double potential = 0.0, created = 0.0, removed = 0.0, lost_mass = 0.0, lost_count = 0.0;
    for (std::size_t b = 0; b < ps.bodies(); ++b) potential -= ps.mass[b] * dot(sc.settings.gravity, ps.position[b]);
    for (const auto& f : factories) created += f.report().total_mass;
    for (const auto& s : sinks) {
      for (const double m : s.mass) removed += m;
    }
    for (std::size_t k = 0; k < lost.mass.size(); ++k)
      lost_mass += lost.mass[k], lost_count += static_cast<double>(lost.count[k]);
    const double ke = ps.kinetic_energy();
    const auto n = static_cast<double>(ps.bodies());
    v = {sim.time(),
         n,
         ke,
         n > 0 ? ke / n : 0.0,
         potential,
         sim.max_overlap_ratio(),
         static_cast<double>(sim.contacts()),
         created,
         removed,
         lost_mass,
         lost_count};
    for (const auto& s : sc.sensors) {
      switch (s.kind) {
        case SensorSpec::Kind::region: {
          const RegionReading r = read_region(sim, s.region);
          v.insert(v.end(), {r.mass, static_cast<double>(r.count), r.bulk_density, r.bulk_density_exact,
                             r.packing_fraction, r.coordination});
          v.insert(v.end(), r.mass_fraction.begin(), r.mass_fraction.end());
          break;
        }
        case SensorSpec::Kind::part: {
          const Part& p = sim.part(s.part);
          const double along = dot(p.force, s.axis);
          v.push_back(along);
          if (s.area > 0.0) v.push_back(along / s.area);
          v.insert(v.end(), {p.force.x, p.force.y, p.force.z, p.pose.position.z});
          break;
        }
        case SensorSpec::Kind::heap: {
          const HeapProfile h = heap_profile(sim, s.centre.x, s.centre.y, s.outer, s.rings);
          double top = 0.0;
          for (const double x : h.height) top = std::isfinite(x) ? std::max(top, x) : top;
          v.insert(v.end(), {top, h.angle * 180.0 / std::numbers::pi});
          break;
        }
      }
    }
    return v;
  }

  double value(const std::string& name) const {
    const auto all = values();
    return all[static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin())];
  }
};

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  const auto t = static_cast<long>(s + 0.5);
  return t >= 3600 ? fmt::format("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
                   : fmt::format("{}:{:02}", t / 60, t % 60);
}

nlohmann::ordered_json values_json(const std::vector<std::pair<std::string, double>>& values) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [k, v] : values) j[k] = std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
  return j;
}

}  // namespace

RunReport run_scenario(const Scenario& sc, const RunOptions& options) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec) throw InputError("cannot create the output folder: " + ec.message()).with_key(options.out_dir);
#ifdef BUSHEL_HAVE_OPENMP
  const int threads = options.threads > 0 ? options.threads : sc.threads;
  if (threads > 0) omp_set_num_threads(threads);
#endif
  RunState st(sc);
  Simulation& sim = st.sim;
  const double dt = sc.settings.dt;
  RunReport report;

  // --- outputs ------------------------------------------------------------------------------
  std::vector<std::size_t> columns;
  for (const auto& name : sc.outputs.series.empty() ? st.names : sc.outputs.series) {
    columns.push_back(static_cast<std::size_t>(std::find(st.names.begin(), st.names.end(), name) - st.names.begin()));
  }
  std::ofstream series(fs::path(options.out_dir) / "timeseries.csv");
  series << "stage";
  for (const std::size_t c : columns) series << ',' << st.names[c];
  series << '\n';
  std::optional<io::FrameWriter> frames;
  if (sc.outputs.frame_interval > 0.0) frames.emplace((fs::path(options.out_dir) / "frames").string());
  double next_row = 0.0, next_frame = 0.0;
  auto write_row = [&](const std::string& stage) {
    const auto v = st.values();
    series << stage;
    for (const std::size_t c : columns) series << ',' << fmt::format("{:.9g}", v[c]);
    series << '\n';
    series.flush();
  };

  const bool tty = options.progress && isatty(fileno(stderr)) != 0;
  const auto wall0 = Clock::now();
  auto last_line = wall0;
  auto wall = [&] { return std::chrono::duration<double>(Clock::now() - wall0).count(); };

  for (std::size_t si = 0; si < sc.stages.size(); ++si) {
    const StageSpec& stage = sc.stages[si];
    const double t0 = sim.time();
    const std::uint64_t steps0 = sim.steps();
    const double wall_stage0 = wall();
    for (const auto& [f, on] : stage.factories) st.factory_on[f] = on;
    for (const auto& [s, on] : stage.sinks) st.sinks[s].enabled = on;
    for (const auto& [p, m] : stage.motions) sim.set_motion(p, shifted(m, t0));
    const double limit = stage.duration ? std::min(*stage.duration, stage.max_time) : stage.max_time;
    std::deque<std::pair<double, double>> history;  // (time, value) of the stable condition
    std::string ended_by;
    while (true) {
      const double elapsed = sim.time() - t0;
      // --- end conditions, in the order the report names them ---
      if (stage.duration && elapsed >= *stage.duration - 0.5 * dt) {
        ended_by = "time";
      } else if (elapsed >= stage.min_time - 0.5 * dt && elapsed > 0.0) {
        if (stage.kinetic_energy && st.kinetic_energy_per_particle() < *stage.kinetic_energy)
          ended_by = "kinetic_energy";
        if (ended_by.empty() && stage.factories_done) {
          bool all = true;
          for (std::size_t f = 0; f < st.factories.size(); ++f)
            all = all && (!st.factory_on[f] || st.factories[f].done());
          if (all) ended_by = "factories_done";
        }
        if (ended_by.empty() && stage.servo_part) {
          const ServoState& s = sim.part(*stage.servo_part).servo;
          if (s.held && s.held_since >= 0.0 && sim.time() - s.held_since >= stage.servo_hold) ended_by = "servo_held";
        }
        if (ended_by.empty() && stage.stable) {
          history.emplace_back(sim.time(), st.value(*stage.stable));
          while (history.size() > 2 && history[1].first <= sim.time() - stage.stable_window) history.pop_front();
          if (history.front().first <= sim.time() - stage.stable_window + 0.5 * dt) {
            double lo = INFINITY, hi = -INFINITY;
            for (const auto& [t, x] : history) lo = std::min(lo, x), hi = std::max(hi, x);
            const double scale = std::max(std::abs(lo), std::abs(hi));
            if (hi - lo <= stage.stable_tolerance * scale) ended_by = "stable";
          }
        }
      }
      if (ended_by.empty() && elapsed >= stage.max_time - 0.5 * dt) ended_by = "max_time";
      if (!ended_by.empty()) break;

      // --- outputs due now ---
      if (sim.time() >= next_row - 0.5 * dt) {
        write_row(stage.name);
        next_row += sc.outputs.series_interval;
      }
      if (frames && sim.time() >= next_frame - 0.5 * dt) {
        frames->write(sim);
        next_frame += sc.outputs.frame_interval;
      }

      // --- advance to the next check, output or end of stage ---
      double span = std::min(sc.check_interval, limit - elapsed);
      span = std::min(span, next_row - sim.time());
      if (frames) span = std::min(span, next_frame - sim.time());
      const auto n = static_cast<std::uint64_t>(std::max(1.0, std::round(span / dt)));
      const double before = sim.time();
      sim.step(n);
      report.particle_steps += static_cast<double>(n) * static_cast<double>(sim.particles().bodies());
      for (std::size_t f = 0; f < st.factories.size(); ++f) {
        if (!st.factory_on[f]) continue;
        const FactorySpec& spec = st.factories[f].spec();
        const double active = std::max(0.0, std::min(sim.time(), spec.stop) - std::max(before, spec.start));
        if (active > 0.0) st.factories[f].run(sim, active);
      }
      apply_sinks(sim, st.sinks, sc.domain, st.lost);

      if (options.progress) {
        const auto now = Clock::now();
        const double since = std::chrono::duration<double>(now - last_line).count();
        if (tty ? since >= 0.25 : since >= options.progress_interval) {
          last_line = now;
          const double w = wall() - wall_stage0;
          const double rate = w > 0.0 ? (sim.time() - t0) / w : 0.0;  // simulated s per wall s
          const double eta = rate > 0.0 ? (limit - (sim.time() - t0)) / rate : std::numeric_limits<double>::infinity();
          fmt::print(stderr, "{}stage {}/{} {}  t = {:.4f} s  particles {}  {:.0f} steps/s  stage ETA {}{}{}",
                     tty ? "\r" : "", si + 1, sc.stages.size(), stage.name, sim.time(), sim.particles().bodies(),
                     static_cast<double>(sim.steps() - steps0) / std::max(w, 1e-9),
                     stage.duration ? "" : "<= ", format_duration(eta), tty ? "   " : "\n");
        }
      }
    }
    StageReport sr{stage.name, ended_by, t0, sim.time(), sim.steps() - steps0, {}};
    const auto v = st.values();
    for (std::size_t k = 0; k < v.size(); ++k) sr.values.emplace_back(st.names[k], v[k]);
    if (options.progress) {
      fmt::print(stderr, "{}stage {}/{} {} ended by {} at t = {:.4f} s ({} steps)\n", tty ? "\r" : "", si + 1,
                 sc.stages.size(), stage.name, ended_by, sim.time(), sr.steps);
    }
    if (ended_by == "max_time" && (stage.kinetic_energy || stage.factories_done || stage.servo_part || stage.stable)) {
      report.warnings.push_back(
          fmt::format("stage '{}' ended at its time limit before its condition was met", stage.name));
    }
    report.stages.push_back(std::move(sr));
  }
  write_row("end");
  if (frames) frames->write(sim);
  report.steps = sim.steps();
  report.simulated_time = sim.time();
  report.wall_time = wall();
  for (const auto& f : st.factories) {
    if (!f.done()) {
      report.warnings.push_back(
          fmt::format("factory '{}' created {:.4g} of its total {:.4g}{}", f.spec().name,
                      f.spec().total_by_mass ? f.report().total_mass : static_cast<double>(f.report().total_count),
                      f.spec().total, f.spec().total_by_mass ? " kg" : " particles"));
    }
  }
  double lost_count = 0.0;
  for (const auto c : st.lost.count) lost_count += static_cast<double>(c);
  if (lost_count > 0) report.warnings.push_back(fmt::format("{:.0f} particles left the domain", lost_count));

  // --- summary.json ---------------------------------------------------------------------------
  nlohmann::ordered_json j;
  j["scenario"] = fs::absolute(sc.document.file).string();
  nlohmann::ordered_json overrides = nlohmann::ordered_json::array();
  for (const auto& o : sc.document.overrides) overrides.push_back(o.path + "=" + o.value);
  j["overrides"] = overrides;
  j["parameters"] = sc.document.parameters;
  YAML::Emitter echo;
  echo << sc.document.root;
  j["echo"] = std::string(echo.c_str());
  j["dt_s"] = dt;
  j["rayleigh_step_s"] = sc.rayleigh_step;
  j["steps"] = report.steps;
  j["simulated_time_s"] = report.simulated_time;
  j["wall_time_s"] = report.wall_time;
  j["particle_steps_per_s"] = report.wall_time > 0.0 ? report.particle_steps / report.wall_time : 0.0;
  nlohmann::ordered_json stages = nlohmann::ordered_json::array();
  for (const auto& s : report.stages) {
    stages.push_back({{"name", s.name},
                      {"ended_by", s.ended_by},
                      {"start_s", s.start},
                      {"end_s", s.end},
                      {"steps", s.steps},
                      {"values", values_json(s.values)}});
  }
  j["stages"] = stages;
  nlohmann::ordered_json factories = nlohmann::ordered_json::array();
  for (const auto& f : st.factories) {
    nlohmann::ordered_json types = nlohmann::ordered_json::object();
    const auto achieved = f.achieved_fractions();
    for (std::size_t k = 0; k < f.spec().types.size(); ++k) {
      types[st.type_names[f.spec().types[k]]] = {{"count", f.report().count[k]},
                                                 {"mass_kg", f.report().mass[k]},
                                                 {"fraction", achieved[k]},
                                                 {"target_fraction", f.spec().fractions[k]}};
    }
    factories.push_back({{"name", f.spec().name},
                         {"fractions_by", f.spec().fractions_by_mass ? "mass" : "count"},
                         {"count", f.report().total_count},
                         {"mass_kg", f.report().total_mass},
                         {"done", f.done()},
                         {"types", types}});
  }
  j["factories"] = factories;
  auto sink_json = [&](const Sink& s) {
    nlohmann::ordered_json types = nlohmann::ordered_json::object();
    std::size_t count = 0;
    double mass = 0.0;
    for (std::size_t k = 0; k < s.count.size(); ++k) {
      types[st.type_names[k]] = {{"count", s.count[k]}, {"mass_kg", s.mass[k]}};
      count += s.count[k];
      mass += s.mass[k];
    }
    return nlohmann::ordered_json{{"name", s.name}, {"count", count}, {"mass_kg", mass}, {"types", types}};
  };
  nlohmann::ordered_json sinks = nlohmann::ordered_json::array();
  for (const auto& s : st.sinks) sinks.push_back(sink_json(s));
  j["sinks"] = sinks;
  j["lost"] = sink_json(st.lost);
  j["final"] =
      values_json(report.stages.empty() ? std::vector<std::pair<std::string, double>>{} : report.stages.back().values);
  j["warnings"] = report.warnings;
  io::write_file_atomically((fs::path(options.out_dir) / "summary.json").string(), j.dump(2) + "\n");
  return report;
}

}  // namespace bushel
