// stages: what each switches and moves, and its end conditions (until:).

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "scenario_reading.hpp"

namespace bushel::scenario_reading {
namespace {

namespace dim = units::dim;

// The stages' time limits against their time steps: a step far too short for the run (a
// template sphere of 1e-300 mm) would make a run that never ends.
void check_step_count(const Scenario& sc, const ScenarioNode& stages) {
  double steps = 0.0;
  for (const StageSpec& s : sc.stages) {
    if (!s.enabled) continue;
    const double limit = s.duration ? std::min(*s.duration, s.max_time) : s.max_time;
    steps += limit / s.dt.value_or(sc.settings.dt);
  }
  if (!(steps <= sc.guards.max_steps)) {
    throw stages.error(fmt::format(
        "the stages' time limits need up to {:.3g} steps of {:.3g} s, more than the guard's {:.3g} "
        "(simulation.guards.max_steps): a time step far too short for the run (a particle far too small?) or "
        "a time limit far too long",
        steps, sc.settings.dt, sc.guards.max_steps));
  }
}

// enable: and disable: factories, sinks and parts by name (one list of all, so a typo is
// matched against all).
void read_switches(const ScenarioNode& s, StageSpec& stage, const ReadContext& cx) {
  for (const auto& [key, on] : {std::pair<const char*, bool>{"enable", true}, {"disable", false}}) {
    if (const auto list = s.find(key)) {
      std::vector<std::string> all = cx.factory_names;
      all.insert(all.end(), cx.sink_names.begin(), cx.sink_names.end());
      all.insert(all.end(), cx.part_names.begin(), cx.part_names.end());
      for (const ScenarioNode& item : list->items()) {
        const std::size_t k = index_in(item, all, "factory, sink or part");
        if (k < cx.factory_names.size()) {
          stage.factories.emplace_back(k, on);
        } else if (k < cx.factory_names.size() + cx.sink_names.size()) {
          stage.sinks.emplace_back(k - cx.factory_names.size(), on);
        } else {
          stage.parts.emplace_back(k - cx.factory_names.size() - cx.sink_names.size(), on);
        }
      }
    }
  }
}

// motions: each part's motion in the stage.
void read_stage_motions(const ScenarioNode& motions, StageSpec& stage, const Scenario& sc, const ReadContext& cx) {
  for (const auto& [pname, list] : motions.entries()) {
    const std::size_t part = index_named(list, pname, cx.part_names, "part");
    Motion motion = read_motion(list);
    try {  // what the part's shape allows, as Simulation::set_motion will check
      validate_motion(sc.parts[part].shape, motion);
    } catch (const InputError& e) {
      throw list.error(e.problem());
    }
    stage.motions.emplace_back(part, std::move(motion));
  }
}

// until: servo_held:, reached: and stable:, the conditions that name a part or a value.
void read_named_conditions(const ScenarioNode& until, StageSpec& stage, const Scenario& sc, const ReadContext& cx) {
  const std::vector<std::string>& values = cx.values;
  if (const auto sh = until.find("servo_held")) {
    sh->allow_only({"part", "hold"});
    stage.servo_part = index_in(sh->at("part"), cx.part_names, "part");
    stage.servo_hold = sh->non_negative_or("hold", dim::time, 0.0);
    bool servo = sc.parts[*stage.servo_part].motion.has_servo;
    for (const auto& [p, m] : stage.motions) servo = servo || (p == *stage.servo_part && m.has_servo);
    if (!servo) throw sh->at("part").error("this part has no servo (motion: - servo: ...)");
  }
  if (const auto r = until.find("reached")) {
    r->allow_only({"value", "above", "below"});
    stage.reached = values[index_in(r->at("value"), values, "value")];
    const std::string side = r->one_of({"above", "below"});
    stage.reached_above = side == "above";
    stage.reached_threshold =
        sc.value_from_si(*stage.reached, r->at(side).quantity(sc.value_dimension(*stage.reached)));
  }
  if (const auto sb = until.find("stable")) {
    sb->allow_only({"value", "tolerance", "window"});
    stage.stable = values[index_in(sb->at("value"), values, "value")];
    if (sb->has("tolerance")) stage.stable_tolerance = sb->at("tolerance").quantity(dim::dimensionless);
    stage.stable_window = sb->positive_or("window", dim::time, 0.05);
  }
}

// until: the stage's end conditions.
void read_until(const ScenarioNode& until, StageSpec& stage, const Scenario& sc, const ReadContext& cx) {
  until.allow_only(
      {"time", "kinetic_energy", "factories_done", "servo_held", "reached", "stable", "min_time", "max_time"});
  if (until.has("time")) stage.duration = until.positive("time", dim::time);
  if (until.has("kinetic_energy")) stage.kinetic_energy = until.positive("kinetic_energy", dim::energy);
  stage.factories_done = until.boolean_or("factories_done", false);
  read_named_conditions(until, stage, sc, cx);
  stage.min_time = until.non_negative_or("min_time", dim::time, 0.0);
  if (until.has("max_time")) stage.max_time = until.positive("max_time", dim::time);
  if (!stage.duration && !std::isfinite(stage.max_time)) {
    throw until.error("expected 'time' or 'max_time': every stage needs a time limit");
  }
}

StageSpec read_stage(const ScenarioNode& s, const Scenario& sc, const ReadContext& cx) {
  s.allow_only({"name", "enabled", "time_step", "enable", "disable", "motions", "until"});
  StageSpec stage;
  stage.name = s.at("name").text();
  if (std::any_of(sc.stages.begin(), sc.stages.end(), [&](const StageSpec& x) { return x.name == stage.name; })) {
    throw s.at("name").error("a second stage named '" + stage.name +
                             "': results and reports name stages, so each "
                             "name must be unique");
  }
  stage.enabled = s.boolean_or("enabled", true);
  if (s.has("time_step")) stage.dt = read_time_step(s, sc, stage.time_step_rule);
  read_switches(s, stage, cx);
  if (const auto motions = s.find("motions")) read_stage_motions(*motions, stage, sc, cx);
  read_until(s.at("until"), stage, sc, cx);
  return stage;
}

}  // namespace

void read_stages(const ScenarioNode& stages, Scenario& sc, const ReadContext& cx) {
  for (const ScenarioNode& s : stages.items()) sc.stages.push_back(read_stage(s, sc, cx));
  if (std::none_of(sc.stages.begin(), sc.stages.end(), [](const StageSpec& x) { return x.enabled; }))
    throw stages.error("expected at least one stage that is not skipped (enabled: false)");
  check_step_count(sc, stages);
}

}  // namespace bushel::scenario_reading
