// `bushel run SCENARIO.yaml --out DIR` and `bushel validate SCENARIO.yaml`.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

#include <nlohmann/json.hpp>

#include "bushel/core/input_error.hpp"
#include "bushel/scenario/run_summary.hpp"
#include "bushel/scenario/scenario.hpp"
#include "bushel/scenario/scenario_run.hpp"
#include "commands.hpp"

namespace bushel::cli {
namespace {

struct RunCommandOptions {
  std::string scenario, out, restart, stop_at;
  std::vector<std::string> sets;
  int threads = 0;
  double checkpoint_minutes = 5.0;
  bool quiet = false;
  bool json = false;
  bool overwrite = false;
};

Scenario load(const RunCommandOptions& o) {
  std::vector<Override> overrides;
  for (const auto& s : o.sets) overrides.push_back(parse_override(s));
  return read_scenario(load_scenario_document(o.scenario, overrides));
}

std::string time_step_text(double dt, const TimeStepRule& rule, const Scenario& sc) {
  const std::string steps = fmt::format("Rayleigh step {:.4g} us, critical step {:.4g} us", sc.rayleigh_step * 1e6,
                                        sc.critical_step.dt * 1e6);
  return fmt::format("{:.4g} us ({}{})", dt * 1e6, rule.fraction > 0.0 ? rule.text() + "; " : "", steps);
}

void describe(const Scenario& sc) {
  fmt::print("{}: valid\n", sc.document.file);
  fmt::print("  time step      {}\n", time_step_text(sc.settings.dt, sc.time_step_rule, sc));
  const CriticalStep& c = sc.critical_step;
  fmt::print("  critical step  {:.4g} us: {} contact {}, zeta {:.2f} (docs/physics.md section 3)\n", c.dt * 1e6,
             c.tangential ? "tangential" : "normal", c.pair, c.zeta);
  const double limit = sc.settings.tangential_damping_limit;
  fmt::print("  damping limit  {}\n", std::isfinite(limit)
                                          ? fmt::format("tangential, {:g} of the sliding velocity per step", limit)
                                          : std::string("off (the model's tangential damping)"));
  fmt::print("  particle types {}\n", sc.types.size());
  fmt::print("  parts          {}\n", sc.parts.size());
  fmt::print("  factories      {}\n", sc.factories.size());
  fmt::print("  sensors        {}\n", sc.sensors.size());
  for (const auto& s : sc.stages) {
    fmt::print("  stage          {}{}{}\n", s.name, s.enabled ? "" : " (skipped)",
               s.dt ? ", time step " + time_step_text(*s.dt, s.time_step_rule, sc) : "");
  }
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunCommandOptions>();
  auto* run = app.add_subcommand("run", "Run a scenario file (docs/scenarios.md), or continue one with --restart");
  run->add_option("scenario", o->scenario, "Scenario file (YAML)");
  run->add_option("--out", o->out, "Output folder (summary.json, timeseries.csv, frames/, checkpoint.bin)");
  run->add_option("--restart", o->restart, "Continue the run in this folder from its checkpoint (no scenario)");
  run->add_option("--set", o->sets, "Override a value: path.to.key=value (repeatable)");
  run->add_option("--threads", o->threads, "a fixed thread count (0 = the scenario's setting, by default auto)")
      ->capture_default_str();
  run->add_option("--checkpoint-every", o->checkpoint_minutes,
                  "Minutes of wall time between checkpoints (0: only on Ctrl-C)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  run->add_option("--stop-at", o->stop_at,
                  "Stop at this simulated time (e.g. 0.5s) as Ctrl-C would: checkpoint written, continue with "
                  "--restart");
  run->add_flag("--overwrite", o->overwrite,
                "Replace the outputs of another run in --out (they are removed first); without it such a folder "
                "is refused");
  run->add_flag("--quiet", o->quiet, "No progress lines");
  run->add_flag("--json", o->json,
                "At the end print the results as JSON (values in SI, angles in degrees; null: not computed)");
  run->callback([o] {
    RunOptions options;
    if (!o->stop_at.empty()) options.interrupt_at = option_quantity("--stop-at", o->stop_at, units::dim::time);
    options.threads = o->threads;
    options.progress = !o->quiet;
    options.checkpoint_interval = 60.0 * o->checkpoint_minutes;
    options.overwrite = o->overwrite;
    RunReport r;
    if (!o->restart.empty()) {
      if (!o->scenario.empty() || !o->out.empty() || !o->sets.empty() || o->overwrite) {
        throw InputError(
            "--restart DIR continues the run in DIR with its own scenario; give no scenario, --out, --set or "
            "--overwrite")
            .with_key("--restart");
      }
      options.out_dir = o->restart;
      r = resume_scenario(options);
    } else {
      if (o->scenario.empty()) throw InputError("expected a scenario file (or --restart DIR)").with_key("scenario");
      if (o->out.empty()) throw InputError("expected an output folder").with_key("--out");
      options.out_dir = o->out;
      r = run_scenario(load(*o), options);
    }
    if (!r.failed.empty()) {  // checkpoint and summary (marked failed) written
      fmt::print(stderr, "bushel: error: the run failed {}; its checkpoint and summary (marked failed) are in {}\n",
                 r.failed, options.out_dir);
      std::exit(3);
    }
    // checkpoint written; 128 + the signal, as a shell reports one (130 for Ctrl-C, 143 for SIGTERM)
    if (r.interrupted) std::exit(r.at_stop_time ? 0 : 128 + r.signal);
    if (o->json) {  // for programs: `bushel doe run --scenario` reads the results from here
      const RunSummary& summary = r.summary;
      nlohmann::ordered_json results = nlohmann::ordered_json::object(), units = nlohmann::ordered_json::object();
      for (const RunResult& res : summary.results) {
        results[res.name] = res.value ? nlohmann::ordered_json(*res.value) : nlohmann::ordered_json();
        units[res.name] = res.unit;
      }
      const nlohmann::ordered_json j = {{"summary", summary.file},
                                        {"results", results},
                                        {"units", units},
                                        {"simulated_time_s", summary.simulated_time},
                                        {"wall_time_s", summary.wall_time},
                                        {"particle_steps_per_s", summary.particle_steps_per_s},
                                        {"warnings", summary.warnings}};
      fmt::print("{}\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
      return;
    }
    for (const auto& s : r.stages) {
      fmt::print("stage {:<12} ended by {:<15} t = {:.4f} s\n", s.name, s.ended_by, s.end);
    }
    // The headline: every bulk density the sensors measured at the end.
    const StageReport& last = r.stages.back();
    for (const auto& [name, value] : last.values) {
      if (!name.ends_with(".bulk_density")) continue;
      const auto below =
          surface_shortfall(last, name.substr(0, name.size() - std::string_view(".bulk_density").size()));
      fmt::print("{:<28} {:.1f} kg/m3{}\n", name, value,
                 below
                     ? fmt::format("  NOT FULL: the grain surface lies {:.1f} mm below the sensor's top", 1e3 * *below)
                     : "");
    }
    fmt::print("{} steps, {:.3f} s simulated, {:.1f} s wall, {:.3g} particle-steps/s\n", r.steps, r.simulated_time,
               r.wall_time, r.wall_time > 0.0 ? r.particle_steps / r.wall_time : 0.0);
    for (const auto& w : r.warnings) fmt::print("warning: {}\n", w);
    fmt::print("results in {}/summary.json\n", options.out_dir);
  });

  auto v = std::make_shared<RunCommandOptions>();
  auto* validate = app.add_subcommand("validate", "Check a scenario file without running it");
  validate->add_option("scenario", v->scenario, "Scenario file (YAML)")->required();
  validate->add_option("--set", v->sets, "Override a value: path.to.key=value (repeatable)");
  validate->callback([v] { describe(load(*v)); });
}

}  // namespace bushel::cli
