#include "bushel/scenario/scenario.hpp"

#include <filesystem>
#include <map>
#include <numbers>

#include "bushel/scenario/scenario_node.hpp"
#include "scenario_reading.hpp"

namespace bushel {

std::vector<std::string> SensorSpec::values(const std::vector<std::string>& type_names) const {
  switch (kind) {
    case Kind::region: {
      std::vector<std::string> v = {"mass",         "count",  "bulk_density",  "bulk_density_exact", "packing_fraction",
                                    "coordination", "volume", "surface_margin"};
      for (const auto& t : type_names) v.push_back("fraction_" + t);
      return v;
    }
    case Kind::part: {
      std::vector<std::string> v = {"force"};
      if (area > 0.0) v.push_back("pressure");
      v.insert(v.end(), {"force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z", "position_z", "angle"});
      return v;
    }
    case Kind::heap:
      return {"height", "angle"};
    case Kind::flow:
      return {"mass", "rate"};
  }
  return {};
}

const std::vector<std::string>& global_value_names() {
  static const std::vector<std::string> names = {"time",
                                                 "particles",
                                                 "kinetic_energy",
                                                 "kinetic_energy_per_particle",
                                                 "potential_energy",
                                                 "max_overlap_ratio",
                                                 "unbalanced_force",
                                                 "contacts",
                                                 "created_mass",
                                                 "removed_mass",
                                                 "lost_mass",
                                                 "lost_count"};
  return names;
}

units::Dimension value_dimension(const std::string& value_name) {
  namespace dim = units::dim;
  const std::string v = value_name.substr(value_name.rfind('.') + 1);
  static const std::map<std::string, units::Dimension> by_name = {{"time", dim::time},
                                                                  {"kinetic_energy", dim::energy},
                                                                  {"kinetic_energy_per_particle", dim::energy},
                                                                  {"potential_energy", dim::energy},
                                                                  {"created_mass", dim::mass},
                                                                  {"removed_mass", dim::mass},
                                                                  {"lost_mass", dim::mass},
                                                                  {"mass", dim::mass},
                                                                  {"bulk_density", dim::density},
                                                                  {"bulk_density_exact", dim::density},
                                                                  {"volume", dim::volume},
                                                                  {"force", dim::force},
                                                                  {"force_x", dim::force},
                                                                  {"force_y", dim::force},
                                                                  {"force_z", dim::force},
                                                                  {"pressure", dim::pressure},
                                                                  {"torque_x", dim::energy},  // N m
                                                                  {"torque_y", dim::energy},
                                                                  {"torque_z", dim::energy},
                                                                  {"position_z", dim::length},
                                                                  {"surface_margin", dim::length},
                                                                  {"height", dim::length},
                                                                  {"rate", dim::mass_flow},
                                                                  {"start", dim::time},
                                                                  {"end", dim::time},
                                                                  {"duration", dim::time},
                                                                  {"angle", dim::angle}};
  const auto it = by_name.find(v);
  return it == by_name.end() ? dim::dimensionless : it->second;  // counts, fractions, ratios
}

namespace {
constexpr double degree = std::numbers::pi / 180.0;
}

double value_to_si(const std::string& value_name, double value) {
  return value_dimension(value_name) == units::dim::angle ? value * degree : value;
}

double value_from_si(const std::string& value_name, double value_si) {
  return value_dimension(value_name) == units::dim::angle ? value_si / degree : value_si;
}

std::string_view result_unit(units::Dimension d) { return d == units::dim::angle ? "deg" : units::si_symbol(d); }

double result_value(const units::Quantity& q) { return q.dimension == units::dim::angle ? q.value / degree : q.value; }

units::Quantity evaluate_result(const ResultSpec& result,
                                const std::function<double(const std::string&, const std::string&)>& value) {
  return units::evaluate(result.expression, [&](const std::string& name) {
    const std::size_t dot = name.find('.');
    if (dot == std::string::npos) {
      throw InputError("'" + name + "' is not a stage's value (expected stage.value, e.g. fill.cup.bulk_density)");
    }
    return units::Quantity{value_to_si(name, value(name.substr(0, dot), name.substr(dot + 1))), value_dimension(name)};
  });
}

std::vector<std::string> Scenario::value_names() const {
  std::vector<std::string> names = global_value_names();
  std::vector<std::string> type_names;
  for (const auto& t : types) type_names.push_back(t.name);
  for (const auto& s : sensors) {
    for (const auto& v : s.values(type_names)) names.push_back(s.name + "." + v);
  }
  return names;
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
  read_simulation_time_step(sim, sc);
  if (const auto c = root.find("contacts")) read_contacts(*c, sc, cx);
  if (const auto parts = root.find("parts")) read_parts(*parts, sc, cx);
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
