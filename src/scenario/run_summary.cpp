#include "bushel/scenario/run_summary.hpp"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "bushel/core/input_error.hpp"
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

StageReport read_stage(const Json& s) {
  StageReport st;
  st.name = member(s, "name", Json::value_t::string, "a stage name").get<std::string>();
  try {
    st.ended_by = member(s, "ended_by", Json::value_t::string, "what ended the stage").get<std::string>();
    st.start = number(s, "start_s");
    st.end = number(s, "end_s");
    st.steps = member(s, "steps", Json::value_t::number_float, "a step count").get<std::uint64_t>();
    for (const auto& [name, v] : member(s, "values", Json::value_t::object, "the stage's values").items()) {
      st.values.emplace_back(name, number_or_nan(v));
    }
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
    if (!j.is_object() || !j.contains("stages") || !j.contains("results")) {
      throw InputError("expected a run summary written by `bushel run` (with stages and results)");
    }
    out.scenario = member(j, "scenario", Json::value_t::string, "the scenario's path").get<std::string>();
    for (const auto& [name, v] : member(j, "parameters", Json::value_t::object, "the parameters").items()) {
      out.parameters.emplace_back(name, v.is_string() ? v.get<std::string>() : v.dump());
    }
    if (const auto ov = j.find("overrides"); ov != j.end() && ov->is_array()) {
      for (const auto& o : *ov) out.overrides.push_back(o.get<std::string>());
    }
    if (const auto e = j.find("engine"); e != j.end() && e->is_object()) {
      // (absent from summaries written before runs recorded their engine)
      if (const auto b = e->find("builds"); b != e->end() && b->is_array()) {
        for (const auto& x : *b) out.engines.push_back(x.is_string() ? x.get<std::string>() : x.dump());
      }
    }
    out.interrupted = member(j, "interrupted", Json::value_t::boolean, "true or false").get<bool>();
    out.dt = number(j, "dt_s");
    out.steps = member(j, "steps", Json::value_t::number_float, "a step count").get<std::size_t>();
    out.simulated_time = number(j, "simulated_time_s");
    out.wall_time = number(j, "wall_time_s");
    out.particle_steps_per_s = number(j, "particle_steps_per_s");
    for (const auto& s : member(j, "stages", Json::value_t::array, "a list of stages")) {
      try {
        out.stages.push_back(read_stage(s));
      } catch (const InputError& e) {
        throw e.with_key("stages");
      }
    }
    for (const auto& [name, r] : member(j, "results", Json::value_t::object, "the results").items()) {
      RunResult res{name, std::nullopt, "", ""};
      if (r.is_object()) {
        if (r.contains("value") && r["value"].is_number()) res.value = r["value"].get<double>();
        res.unit = r.value("unit", std::string());
        res.not_full = r.value("not_full", std::string());
      } else if (!r.is_null()) {
        throw InputError("expected {value, unit} or null").with_key("results." + name);
      }
      out.results.push_back(std::move(res));
    }
    if (const auto fs_ = j.find("factories"); fs_ != j.end()) {
      for (const auto& f : *fs_) {
        try {
          out.factories.push_back(read_factory(f));
        } catch (const InputError& e) {
          throw e.with_key("factories");
        }
      }
    }
    if (const auto w = j.find("warnings"); w != j.end() && w->is_array()) {
      for (const auto& x : *w) out.warnings.push_back(x.is_string() ? x.get<std::string>() : x.dump());
    }
  } catch (const InputError& e) {
    throw e.at(out.file);
  } catch (const Json::exception& e) {
    throw InputError(std::string("unexpected content: ") + e.what()).at(out.file);
  }
  return out;
}

}  // namespace bushel
