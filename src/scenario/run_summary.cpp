#include "bushel/scenario/run_summary.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "bushel/core/input_error.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/csv.hpp"

namespace bushel {

namespace {

using Json = nlohmann::ordered_json;

// The member `key` of `j`, or an error naming the key and what was expected.
const Json& member(const Json& j, const std::string& key, Json::value_t kind, const char* expected) {
  const auto it = j.find(key);
  const bool number_ok = kind == Json::value_t::number_float && it != j.end() && it->is_number();
  if (it == j.end() || (!number_ok && it->type() != kind)) {
    throw InputError(std::string("expected ") + expected + (it == j.end() ? ", found none" : ", found another kind"))
        .with_key(key);
  }
  return *it;
}

double number(const Json& j, const std::string& key) {
  return member(j, key, Json::value_t::number_float, "a number").get<double>();
}

// A number that the run writes as null when it is not finite (NaN: an empty sensor).
double number_or_nan(const Json& v) {
  return v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

// A string member if there is one (keys added to the summary since its first version).
std::string string_or(const Json& j, const std::string& key, const std::string& fallback = "") {
  const auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : fallback;
}

double number_or(const Json& j, const std::string& key, double fallback) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : fallback;
}

// Values as {"name": number or null}, in order.
std::vector<std::pair<std::string, double>> read_values(const Json& j) {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& [name, v] : j.items()) out.emplace_back(name, number_or_nan(v));
  return out;
}

// Numbers written as null when they are not finite (NaN: an empty sensor).
Json values_json(const std::vector<std::pair<std::string, double>>& values) {
  Json j = Json::object();
  for (const auto& [k, v] : values) j[k] = std::isfinite(v) ? Json(v) : Json();
  return j;
}

// Each profile as {"sensor": {"radius_m": [...], "height_m": [...]}} (null for empty rings).
Json profiles_json(const std::vector<StageReport::Profile>& profiles) {
  Json j = Json::object();
  for (const auto& p : profiles) {
    Json heights = Json::array();
    for (const double h : p.height) heights.push_back(std::isfinite(h) ? Json(h) : Json());
    j[p.sensor] = {{"radius_m", p.radius}, {"height_m", heights}};
  }
  return j;
}

Json stage_json(const StageReport& s) {
  return {{"name", s.name},
          {"ended_by", s.ended_by},
          {"start_s", s.start},
          {"end_s", s.end},
          {"steps", s.steps},
          {"dt_s", s.dt},
          {"values", values_json(s.values)},
          {"heap_profiles", profiles_json(s.profiles)}};
}

// The results as {"name": {"value": .., "unit": .., "not_full": ..}}, null where not computed.
Json results_json(const std::vector<RunResult>& results) {
  Json j = Json::object();
  for (const RunResult& r : results) {
    if (!r.computed) {
      j[r.name] = nullptr;
      continue;
    }
    j[r.name] = {{"value", r.value ? Json(*r.value) : Json()}, {"unit", r.unit}};
    if (!r.not_full.empty()) j[r.name]["not_full"] = r.not_full;
  }
  return j;
}

Json factory_json(const FactorySummary& f) {
  Json types = Json::object();
  for (const FactoryTypeSummary& t : f.types) {
    types[t.type] = {
        {"count", t.count}, {"mass_kg", t.mass}, {"fraction", t.fraction}, {"target_fraction", t.target_fraction}};
  }
  return {{"name", f.name},   {"fractions_by", f.by_mass ? "mass" : "count"},
          {"count", f.count}, {"mass_kg", f.mass},
          {"done", f.done},   {"types", types}};
}

Json sink_json(const SinkSummary& k) {
  Json types = Json::object();
  for (const SinkSummary::Type& t : k.types) types[t.type] = {{"count", t.count}, {"mass_kg", t.mass}};
  return Json{{"name", k.name}, {"count", k.count}, {"mass_kg", k.mass}, {"types", types}};
}

// A sink's summary, if `j` is one (summaries before sinks were summarised have none).
SinkSummary read_sink(const Json& j) {
  SinkSummary k;
  if (!j.is_object()) return k;
  k.name = string_or(j, "name");
  k.count = j.value("count", std::size_t{0});
  k.mass = number_or(j, "mass_kg", 0.0);
  if (const auto ts = j.find("types"); ts != j.end() && ts->is_object()) {
    for (const auto& [type, t] : ts->items()) {
      k.types.push_back({type, t.value("count", std::size_t{0}), number_or(t, "mass_kg", 0.0)});
    }
  }
  return k;
}

StageReport read_stage(const Json& s) {
  StageReport st;
  st.name = member(s, "name", Json::value_t::string, "a stage name").get<std::string>();
  try {
    st.ended_by = member(s, "ended_by", Json::value_t::string, "what ended the stage").get<std::string>();
    st.start = number(s, "start_s");
    st.end = number(s, "end_s");
    st.steps = member(s, "steps", Json::value_t::number_float, "a step count").get<std::uint64_t>();
    st.dt = number_or(s, "dt_s", 0.0);
    st.values = read_values(member(s, "values", Json::value_t::object, "the stage's values"));
    if (const auto hp = s.find("heap_profiles"); hp != s.end() && hp->is_object()) {
      for (const auto& [sensor, p] : hp->items()) {
        StageReport::Profile profile{sensor, {}, {}};
        for (const auto& r : member(p, "radius_m", Json::value_t::array, "ring radii [m]")) {
          profile.radius.push_back(number_or_nan(r));
        }
        for (const auto& h : member(p, "height_m", Json::value_t::array, "heights [m]")) {
          profile.height.push_back(number_or_nan(h));
        }
        if (profile.radius.size() != profile.height.size()) {
          throw InputError("expected as many heights as radii").with_key("heap_profiles." + sensor);
        }
        st.profiles.push_back(std::move(profile));
      }
    }
  } catch (const InputError& e) {
    throw e.with_key(st.name);
  }
  return st;
}

FactorySummary read_factory(const Json& f) {
  FactorySummary out;
  out.name = member(f, "name", Json::value_t::string, "a factory name").get<std::string>();
  try {
    out.by_mass = f.value("fractions_by", std::string("mass")) == "mass";
    out.count = member(f, "count", Json::value_t::number_float, "a count").get<std::size_t>();
    out.mass = number(f, "mass_kg");
    out.done = f.value("done", false);
    for (const auto& [type, t] : member(f, "types", Json::value_t::object, "the types created").items()) {
      out.types.push_back({type, member(t, "count", Json::value_t::number_float, "a count").get<std::size_t>(),
                           number(t, "mass_kg"), number(t, "fraction"), number(t, "target_fraction")});
    }
  } catch (const InputError& e) {
    throw e.with_key(out.name);
  }
  return out;
}

}  // namespace

std::string RunSummary::scenario_name() const { return std::filesystem::path(scenario).stem().string(); }

std::optional<std::string> RunSummary::parameter(const std::string& name) const {
  const auto it = std::find_if(parameters.begin(), parameters.end(), [&](const auto& p) { return p.first == name; });
  if (it == parameters.end()) return std::nullopt;
  return it->second;
}

const RunResult* RunSummary::result(const std::string& name) const {
  const auto it = std::find_if(results.begin(), results.end(), [&](const RunResult& r) { return r.name == name; });
  return it == results.end() ? nullptr : &*it;
}

const StageReport* RunSummary::stage(const std::string& name) const {
  const auto it = std::find_if(stages.begin(), stages.end(), [&](const StageReport& s) { return s.name == name; });
  return it == stages.end() ? nullptr : &*it;
}

std::vector<std::pair<double, double>> RunSummary::curve(const std::string& x, const std::string& y) const {
  std::vector<std::pair<double, double>> points;
  for (const RunResult& r : results) {
    if (r.name.rfind(x + "_", 0) != 0 || !r.value) continue;
    const RunResult* other = result(y + "_" + r.name.substr(x.size() + 1));
    if (other && other->value) points.emplace_back(*r.value, *other->value);
  }
  std::stable_sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return points;
}

bool names_run(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_directory(path, ec) || std::filesystem::path(path).extension() == ".json";
}

namespace {

void read_header(const Json& j, RunSummary& out) {
  out.scenario = member(j, "scenario", Json::value_t::string, "the scenario's path").get<std::string>();
  for (const auto& [name, v] : member(j, "parameters", Json::value_t::object, "the parameters").items()) {
    out.parameters.emplace_back(name, v.is_string() ? v.get<std::string>() : v.dump());
  }
  if (const auto ov = j.find("overrides"); ov != j.end() && ov->is_array()) {
    for (const auto& o : *ov) out.overrides.push_back(o.get<std::string>());
  }
  if (const auto e = j.find("engine"); e != j.end() && e->is_object()) {
    // (absent from summaries written before runs recorded their engine)
    out.engine_version = string_or(*e, "version");
    out.engine_commit = string_or(*e, "commit");
    out.engine_dirty = e->value("uncommitted_changes", false);
    if (const auto b = e->find("builds"); b != e->end() && b->is_array()) {
      for (const auto& x : *b) out.engines.push_back(x.is_string() ? x.get<std::string>() : x.dump());
    }
  }
  out.echo = string_or(j, "echo");
  out.interrupted = member(j, "interrupted", Json::value_t::boolean, "true or false").get<bool>();
  out.failed = string_or(j, "failed");
  out.dt = number(j, "dt_s");
  out.rayleigh_step = number_or(j, "rayleigh_step_s", 0.0);
  out.critical_step = number_or(j, "critical_step_s", 0.0);
  out.time_step_rule = string_or(j, "time_step_rule");
  out.steps = member(j, "steps", Json::value_t::number_float, "a step count").get<std::size_t>();
  out.simulated_time = number(j, "simulated_time_s");
  out.wall_time = number(j, "wall_time_s");
  out.particle_steps_per_s = number(j, "particle_steps_per_s");
}

void read_results(const Json& j, RunSummary& out) {
  for (const auto& [name, r] : member(j, "results", Json::value_t::object, "the results").items()) {
    RunResult res{name, std::nullopt, "", ""};
    if (r.is_object()) {
      if (r.contains("value") && r["value"].is_number()) res.value = r["value"].get<double>();
      res.unit = r.value("unit", std::string());
      res.not_full = r.value("not_full", std::string());
    } else if (!r.is_null()) {
      throw InputError("expected {value, unit} or null").with_key("results." + name);
    } else {
      res.computed = false;
    }
    out.results.push_back(std::move(res));
  }
}

}  // namespace

void to_json(Json& j, const RunSummary& s) {
  j = Json::object();
  j["scenario"] = s.scenario;
  j["engine"] = {{"version", s.engine_version},
                 {"commit", s.engine_commit},
                 {"uncommitted_changes", s.engine_dirty},
                 {"builds", s.engines}};
  j["overrides"] = s.overrides;
  Json parameters = Json::object();
  for (const auto& [k, v] : s.parameters) parameters[k] = v;
  j["parameters"] = parameters;
  j["echo"] = s.echo;
  j["interrupted"] = s.interrupted;
  j["failed"] = s.failed.empty() ? Json() : Json(s.failed);
  j["dt_s"] = s.dt;
  j["rayleigh_step_s"] = s.rayleigh_step;
  j["critical_step_s"] = s.critical_step;
  j["time_step_rule"] = s.time_step_rule;
  j["steps"] = s.steps;
  j["simulated_time_s"] = s.simulated_time;
  j["wall_time_s"] = s.wall_time;
  j["particle_steps_per_s"] = s.particle_steps_per_s;
  j["stages"] = Json::array();
  for (const StageReport& st : s.stages) j["stages"].push_back(stage_json(st));
  j["results"] = results_json(s.results);
  j["factories"] = Json::array();
  for (const FactorySummary& f : s.factories) j["factories"].push_back(factory_json(f));
  j["sinks"] = Json::array();
  for (const SinkSummary& k : s.sinks) j["sinks"].push_back(sink_json(k));
  j["lost"] = sink_json(s.lost);
  j["final"] = values_json(s.final_values);
  j["final_state_hash"] = s.final_state_hash;
  j["warnings"] = s.warnings;
}

void from_json(const Json& j, RunSummary& out) {
  if (!j.is_object() || !j.contains("stages") || !j.contains("results")) {
    throw InputError("expected a run summary written by `bushel run` (with stages and results)");
  }
  read_header(j, out);
  for (const auto& s : member(j, "stages", Json::value_t::array, "a list of stages")) {
    try {
      out.stages.push_back(read_stage(s));
    } catch (const InputError& e) {
      throw e.with_key("stages");
    }
  }
  read_results(j, out);
  if (const auto fs_ = j.find("factories"); fs_ != j.end()) {
    for (const auto& f : *fs_) {
      try {
        out.factories.push_back(read_factory(f));
      } catch (const InputError& e) {
        throw e.with_key("factories");
      }
    }
  }
  if (const auto ks = j.find("sinks"); ks != j.end() && ks->is_array()) {
    for (const auto& k : *ks) out.sinks.push_back(read_sink(k));
  }
  if (const auto l = j.find("lost"); l != j.end()) out.lost = read_sink(*l);
  if (const auto f = j.find("final"); f != j.end() && f->is_object()) out.final_values = read_values(*f);
  out.final_state_hash = string_or(j, "final_state_hash");
  if (const auto w = j.find("warnings"); w != j.end() && w->is_array()) {
    for (const auto& x : *w) out.warnings.push_back(x.is_string() ? x.get<std::string>() : x.dump());
  }
}

void write_run_summary(const RunSummary& s, const std::string& dir) {
  const Json j = s;
  // (bytes that are not UTF-8 in a name from a file are replaced: a summary is never lost to them)
  io::write_file_atomically((std::filesystem::path(dir) / "summary.json").string(),
                            j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

RunSummary read_run_summary(const std::string& path) {
  namespace fs = std::filesystem;
  RunSummary out;
  out.directory = path;
  out.file = fs::path(path).extension() == ".json" ? path : (fs::path(path) / "summary.json").string();
  std::error_code ec;
  if (!fs::exists(out.file, ec)) {
    throw InputError(fs::is_directory(path, ec) ? "no summary.json here: expected the output folder of `bushel run`"
                                                : "no such run folder or summary file")
        .at(path);
  }
  Json j;
  try {
    j = Json::parse(io::read_text_file(out.file));
  } catch (const Json::parse_error& e) {
    throw InputError(std::string("not valid JSON: ") + e.what()).at(out.file);
  }
  try {
    from_json(j, out);
  } catch (const InputError& e) {
    throw e.at(out.file);
  } catch (const Json::exception& e) {
    throw InputError(std::string("unexpected content: ") + e.what()).at(out.file);
  }
  return out;
}

}  // namespace bushel
