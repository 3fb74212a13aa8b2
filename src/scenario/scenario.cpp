#include "bushel/scenario/scenario.hpp"

#include <fmt/format.h>
#include <filesystem>
#include <map>
#include <numbers>

#include "bushel/scenario/scenario_node.hpp"
#include "scenario_reading.hpp"

namespace bushel {

std::string_view to_string(StageEnd end) {
  switch (end) {
    case StageEnd::time:
      return "time";
    case StageEnd::kinetic_energy:
      return "kinetic_energy";
    case StageEnd::factories_done:
      return "factories_done";
    case StageEnd::servo_held:
      return "servo_held";
    case StageEnd::reached:
      return "reached";
    case StageEnd::stable:
      return "stable";
    case StageEnd::max_time:
      return "max_time";
  }
  return "?";
}

const std::vector<ValueColumn>& global_value_columns() {
  namespace dim = units::dim;
  static const std::vector<ValueColumn> columns = {{"time", dim::time},
                                                   {"particles", dim::dimensionless},
                                                   {"kinetic_energy", dim::energy},
                                                   {"kinetic_energy_per_particle", dim::energy},
                                                   {"potential_energy", dim::energy},
                                                   {"max_overlap_ratio", dim::dimensionless},
                                                   {"unbalanced_force", dim::dimensionless},
                                                   {"contacts", dim::dimensionless},
                                                   {"created_mass", dim::mass},
                                                   {"removed_mass", dim::mass},
                                                   {"lost_mass", dim::mass},
                                                   {"lost_count", dim::dimensionless}};
  return columns;
}

const std::vector<std::string>& global_value_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const ValueColumn& c : global_value_columns()) n.push_back(c.name);
    return n;
  }();
  return names;
}

std::vector<ValueColumn> Scenario::value_columns() const {
  std::vector<ValueColumn> columns = global_value_columns();
  std::vector<std::string> type_names;
  for (const auto& t : types) type_names.push_back(t.name);
  for (const auto& s : sensors) {
    for (auto& c : s.columns(type_names)) columns.push_back({s.name + "." + c.name, c.dimension});
  }
  return columns;
}

std::vector<std::string> Scenario::value_names() const {
  std::vector<std::string> names;
  for (const ValueColumn& c : value_columns()) names.push_back(c.name);
  return names;
}

units::Dimension Scenario::value_dimension(const std::string& value_name) const {
  if (value_name == "start" || value_name == "end" || value_name == "duration") return units::dim::time;
  for (const ValueColumn& c : value_columns()) {
    if (c.name == value_name) return c.dimension;
  }
  return units::dim::dimensionless;
}

namespace {
constexpr double degree = std::numbers::pi / 180.0;
}

double Scenario::value_to_si(const std::string& value_name, double value) const {
  return value_dimension(value_name) == units::dim::angle ? value * degree : value;
}

double Scenario::value_from_si(const std::string& value_name, double value_si) const {
  return value_dimension(value_name) == units::dim::angle ? value_si / degree : value_si;
}

std::string_view result_unit(units::Dimension d) { return d == units::dim::angle ? "deg" : units::si_symbol(d); }

double result_value(const units::Quantity& q) { return q.dimension == units::dim::angle ? q.value / degree : q.value; }

units::Quantity evaluate_result(const ResultSpec& result, const Scenario& scenario,
                                const std::function<double(const std::string&, const std::string&)>& value) {
  return units::evaluate(result.expression, [&](const std::string& name) {
    const std::size_t dot = name.find('.');
    if (dot == std::string::npos) {
      throw InputError("'" + name + "' is not a stage's value (expected stage.value, e.g. fill.cup.bulk_density)");
    }
    const std::string own = name.substr(dot + 1);  // (the stage's own value, or one of the run's)
    const double v = value(name.substr(0, dot), own);
    return units::Quantity{scenario.value_to_si(own, v), scenario.value_dimension(own)};
  });
}

std::string TimeStepRule::text() const {
  switch (basis) {
    case Basis::rayleigh:
      return fmt::format("{:g} rayleigh", fraction);
    case Basis::critical:
      return fmt::format("{:g} critical", fraction);
    case Basis::time:
      break;
  }
  return "time";
}

Scenario read_scenario(ScenarioDocument document) {
  using namespace scenario_reading;
  Scenario sc;
  ReadContext cx;
  const ScenarioNode root(document.root, "", document.file, &document.set_by);
  cx.dir = std::filesystem::path(document.file).parent_path().string();
  root.allow_only({"parameters", "simulation", "materials", "particle_types", "contacts", "parts", "factories", "sinks",
                   "sensors", "stages", "results", "outputs"});
  const ScenarioNode sim = root.at("simulation");
  read_simulation(sim, sc, cx);
  read_materials(root, cx);
  read_particle_types(root, sc, cx);
  if (const auto c = root.find("contacts")) read_contacts(*c, sc, cx);
  if (const auto parts = root.find("parts")) read_parts(*parts, sc, cx);
  read_simulation_time_step(sim, sc);  // (the critical step needs the contacts and the parts)
  if (const auto fs = root.find("factories")) read_factories(*fs, sc, cx);
  if (const auto ss = root.find("sinks")) read_sinks(*ss, sc, cx);
  if (const auto ss = root.find("sensors")) read_sensors(*ss, sc, cx);
  cx.values = sc.value_names();
  read_stages(root.at("stages"), sc, cx);
  if (const auto rs = root.find("results")) read_results(*rs, sc, cx);
  if (const auto out = root.find("outputs")) read_outputs(*out, sc, cx);
  sc.document = std::move(document);
  return sc;
}

}  // namespace bushel
