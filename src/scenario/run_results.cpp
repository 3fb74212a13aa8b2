#include "run_results.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "bushel/core/build_info.hpp"
#include "bushel/core/input_error.hpp"

namespace bushel::scenario_running {
namespace {

// For a density of a region sensor at the end of stage `r` ("cup.bulk_density"): what
// makes it meaningless when the region was not full then (region_sensor.hpp), else "".
std::string not_full_note(const StageReport& r, const std::string& value) {
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
const StageSpec* stage_spec(const Scenario& sc, const std::string& name) {
  const auto s = std::find_if(sc.stages.begin(), sc.stages.end(), [&](const StageSpec& x) { return x.name == name; });
  return s != sc.stages.end() ? &*s : nullptr;
}

// The time step a stage ran with [s].
double stage_dt(const Scenario& sc, const std::string& name) {
  const StageSpec* s = stage_spec(sc, name);
  return s != nullptr && s->dt ? *s->dt : sc.settings.dt;
}

FactorySummary factory_summary(const Factory& f, const std::vector<std::string>& type_names) {
  FactorySummary out{f.spec().name, f.spec().fractions_by_mass, f.report().total_count, f.report().total_mass, {},
                     f.done()};
  const auto achieved = f.achieved_fractions();
  for (std::size_t k = 0; k < f.spec().types.size(); ++k) {
    out.types.push_back(
        {type_names[f.spec().types[k]], f.report().count[k], f.report().mass[k], achieved[k], f.spec().fractions[k]});
  }
  return out;
}

SinkSummary sink_summary(const Sink& k, const std::vector<std::string>& type_names) {
  SinkSummary out{k.name, k.total_count(), k.total_mass(), {}};
  for (std::size_t t = 0; t < k.count.size(); ++t) out.types.push_back({type_names[t], k.count[t], k.mass[t]});
  return out;
}

// The scenario's results from the stages' end values (SI, angles in degrees): not computed
// for one whose stages have not run (an interrupted run), are skipped, or that cannot be
// computed (a warning, unless a stage it names is skipped or the run was interrupted).
std::vector<RunResult> results(const RunReport& report, const Scenario& sc, const RunOptions& o,
                               std::vector<std::string>& warnings) {
  std::vector<RunResult> out;
  for (const ResultSpec& r : sc.results) {
    bool skipped = false;  // it names a stage with enabled: false
    std::string not_full;  // why a density it uses counts empty space
    try {
      const units::Quantity q = evaluate_result(r, sc, [&](const std::string& stage, const std::string& value) {
        const auto s = std::find_if(report.stages.begin(), report.stages.end(),
                                    [&](const StageReport& x) { return x.name == stage; });
        if (s == report.stages.end()) {
          const StageSpec* spec = stage_spec(sc, stage);
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
      out.push_back({r.name, std::isfinite(v) ? std::optional(v) : std::nullopt, std::string(result_unit(q.dimension)),
                     not_full});
      if (!not_full.empty()) warnings.push_back(fmt::format("result '{}' means little: {}", r.name, not_full));
      if (o.progress && !report.interrupted) {
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

}  // namespace

// What summary.json holds: the report, the scenario's results (printed as they are
// computed), what the factories created and the sinks removed, the final values.
RunSummary build_run_summary(const RunReport& report, const RunState& st, const RunOptions& o) {
  const Scenario& sc = st.sc;
  namespace fs = std::filesystem;
  RunSummary s;
  s.directory = o.out_dir;
  s.file = (fs::path(o.out_dir) / "summary.json").string();
  s.scenario = fs::absolute(sc.document.file).string();
  s.engine_version = build_info().version;
  s.engine_commit = build_info().commit;
  s.engine_dirty = build_info().dirty;
  s.engines = report.engines;
  for (const auto& ov : sc.document.overrides) s.overrides.push_back(ov.path + "=" + ov.value);
  s.parameters.assign(sc.document.parameters.begin(), sc.document.parameters.end());
  s.echo = echo_text(sc.document);
  s.interrupted = report.interrupted;
  s.failed = report.failed;
  s.dt = sc.settings.dt;
  s.rayleigh_step = sc.rayleigh_step;
  s.critical_step = sc.critical_step.dt;
  s.time_step_rule = sc.time_step_rule.text();
  s.steps = report.steps;
  s.simulated_time = report.simulated_time;
  s.wall_time = report.wall_time;
  s.particle_steps_per_s = report.wall_time > 0.0 ? report.particle_steps / report.wall_time : 0.0;
  s.stages = report.stages;
  for (StageReport& stage : s.stages) stage.dt = stage_dt(sc, stage.name);
  s.warnings = report.warnings;
  s.results = results(report, sc, o, s.warnings);
  for (const auto& f : st.factories) s.factories.push_back(factory_summary(f, st.type_names));
  for (const auto& k : st.sinks) s.sinks.push_back(sink_summary(k, st.type_names));
  s.lost = sink_summary(st.lost, st.type_names);
  s.final_values = st.named_values();
  s.final_state_hash = fmt::format("{:016x}", state_hash(st.sim.particles()));
  return s;
}

}  // namespace bushel::scenario_running
