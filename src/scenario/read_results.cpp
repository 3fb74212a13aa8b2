// results: and outputs:.

#include <algorithm>

#include <fmt/format.h>

#include "bushel/core/did_you_mean.hpp"
#include "scenario_reading.hpp"

namespace bushel::scenario_reading {
namespace {

namespace dim = units::dim;

// A result's expression, checked now against every stage and value name, with stand-in values
// (distinct, so that a difference of two values is not zero).
void check_result(const ResultSpec& spec, const ScenarioNode& r, const Scenario& sc, const ReadContext& cx) {
  const std::vector<std::string>& values = cx.values;
  double stand_in = 1.0;
  try {
    evaluate_result(spec, sc, [&](const std::string& stage, const std::string& value) {
      const bool known_stage =
          std::any_of(sc.stages.begin(), sc.stages.end(), [&](const StageSpec& x) { return x.name == stage; });
      if (!known_stage) {
        std::vector<std::string> stages;
        for (const auto& x : sc.stages) stages.push_back(x.name);
        throw InputError("unknown stage '" + stage + "'" + did_you_mean(stage, stages));
      }
      const bool own = value == "start" || value == "end" || value == "duration";
      if (!own && std::find(values.begin(), values.end(), value) == values.end()) {
        throw InputError("unknown value '" + value + "'" + did_you_mean(value, values) +
                         " (a stage has start, end, duration and every value of the run)");
      }
      return stand_in += 0.0137;
    });
  } catch (const InputError& e) {
    throw r.error(e.problem());
  }
}

// Outputs are written at checks (scenario_run.cpp), so that what is written never changes
// what is simulated: an interval shorter than the checks' could not be kept.
void not_below_checks(const ScenarioNode& node, double interval, const Scenario& sc) {
  if (interval < sc.check_interval * (1.0 - 1e-9)) {
    throw node.at("interval")
        .error(fmt::format(
            "expected an interval of at least simulation.check_interval ({:g} ms), got {:g} ms: outputs are written "
            "at checks, so that they never change what is simulated (a shorter simulation.check_interval allows it)",
            sc.check_interval * 1e3, interval * 1e3));
  }
}

}  // namespace

void read_results(const ScenarioNode& results, Scenario& sc, const ReadContext& cx) {
  for (const auto& [name, r] : results.entries()) {
    ResultSpec spec{name, r.text()};
    check_result(spec, r, sc, cx);
    sc.results.push_back(std::move(spec));
  }
}

void read_outputs(const ScenarioNode& out, Scenario& sc, const ReadContext& cx) {
  const std::vector<std::string>& values = cx.values;
  out.allow_only({"timeseries", "frames"});
  if (const auto ts = out.find("timeseries")) {
    ts->allow_only({"interval", "values"});
    sc.outputs.series_interval = ts->positive_or("interval", dim::time, 0.01);
    if (ts->has("interval")) not_below_checks(*ts, sc.outputs.series_interval, sc);
    if (const auto v = ts->find("values")) {
      for (const ScenarioNode& item : v->items()) sc.outputs.series.push_back(values[index_in(item, values, "value")]);
    }
  }
  if (const auto fr = out.find("frames")) {
    fr->allow_only({"interval", "format", "fields"});
    sc.outputs.frame_interval = fr->positive("interval", dim::time);
    not_below_checks(*fr, sc.outputs.frame_interval, sc);
    io::FrameOptions& o = sc.outputs.frames;
    if (fr->has("format")) {
      o.encoding =
          fr->at("format").choice({"binary", "ascii"}) == "ascii" ? io::VtuEncoding::ascii : io::VtuEncoding::zlib;
    }
    if (const auto fields = fr->find("fields")) {
      for (const ScenarioNode& item : fields->items()) {
        const std::string f = item.choice({"angular_velocity", "force", "coordination", "contacts"});
        (f == "angular_velocity" ? o.angular_velocity
         : f == "force"          ? o.force
         : f == "coordination"   ? o.coordination
                                 : o.contacts) = true;
      }
    }
  }
}

}  // namespace bushel::scenario_reading
