#include "bushel/report/reference_values.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "bushel/core/input_error.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/units/expression.hpp"

namespace bushel {

namespace embedded {
std::string_view reference_values_csv();  // generated from data/reference_values.csv
}

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::optional<units::Quantity> as_quantity(const std::string& text) {
  try {
    return units::parse_quantity(text);
  } catch (const InputError&) {
    return std::nullopt;
  }
}

bool same_value(const std::string& wanted, const std::string& actual) {
  const auto a = as_quantity(wanted), b = as_quantity(actual);
  if (a && b) {
    return a->dimension == b->dimension &&
           std::abs(a->value - b->value) <= 1e-9 * std::max(std::abs(a->value), std::abs(b->value));
  }
  return lower(wanted) == lower(actual);
}

}  // namespace

std::vector<ReferenceValue> parse_reference_values(std::string_view text, const std::string& source) {
  const io::CsvTable t = io::CsvTable::parse(text, source);
  const std::size_t c_result = t.column("result"), c_value = t.column("value"), c_source = t.column("source");
  const auto optional_column = [&](const char* name) {
    return t.has_column(name) ? std::optional<std::size_t>(t.column(name)) : std::nullopt;
  };
  const auto c_scenario = optional_column("scenario"), c_unit = optional_column("unit"), c_sd = optional_column("sd");
  std::vector<ReferenceValue> out;
  for (const io::CsvRow& row : t.rows()) {
    const auto field = [&](std::size_t c) -> const std::string& { return row.fields[c]; };
    const auto fail = [&](std::size_t c, const std::string& problem) {
      return InputError(problem).at(source, row.line).with_key(t.header()[c]);
    };
    ReferenceValue r;
    r.origin = source + ":" + std::to_string(row.line);
    r.result = field(c_result);
    r.source = field(c_source);
    if (r.result.empty()) throw fail(c_result, "expected the name of a result (e.g. bulk_density)");
    if (r.source.empty()) throw fail(c_source, "expected where the value comes from (e.g. lab, 10 replicates)");
    if (c_scenario) r.scenario = field(*c_scenario);
    const std::string unit = c_unit ? field(*c_unit) : std::string();
    try {
      const units::Quantity q = units::parse_quantity(field(c_value) + (unit.empty() ? "" : " " + unit));
      r.value = q.value;
      r.dimension = q.dimension;
    } catch (const InputError& e) {
      throw fail(c_value, "expected a number (its unit in the unit column): " + e.problem());
    }
    if (c_sd && !field(*c_sd).empty()) {
      std::optional<units::Quantity> sd;
      try {
        sd = units::parse_quantity(field(*c_sd) + (unit.empty() ? "" : " " + unit));
      } catch (const InputError&) {
      }
      if (!sd || !(sd->value >= 0.0)) {
        throw fail(*c_sd, "expected the standard deviation: a number of at least 0 in the unit column's unit, got '" +
                              field(*c_sd) + "'");
      }
      r.sd = sd->value;
    }
    for (std::size_t c = 0; c < t.header().size(); ++c) {
      const bool fixed = c == c_result || c == c_value || c == c_source || c == c_scenario || c == c_unit || c == c_sd;
      if (!fixed && !field(c).empty()) r.conditions.emplace_back(t.header()[c], field(c));
    }
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<ReferenceValue> read_reference_values(const std::string& path) {
  return parse_reference_values(io::read_text_file(path), path);
}

const std::vector<ReferenceValue>& study_reference_values() {
  static const std::vector<ReferenceValue> table =
      parse_reference_values(embedded::reference_values_csv(), "data/reference_values.csv");
  return table;
}

bool reference_applies(const ReferenceValue& reference, const RunSummary& run) {
  if (!reference.scenario.empty() && reference.scenario != run.scenario_name()) return false;
  return std::all_of(reference.conditions.begin(), reference.conditions.end(), [&](const auto& c) {
    const auto actual = run.parameter(c.first);
    return actual && same_value(c.second, *actual);
  });
}

double reference_in_unit_of(const ReferenceValue& reference, const RunResult& result) {
  const units::Quantity unit = units::parse_quantity("1 " + result.unit);
  if (unit.dimension != reference.dimension) {
    throw InputError("the reference for '" + result.name + "' is a " + units::dimension_name(reference.dimension) +
                     ", the run's result a " + units::dimension_name(unit.dimension) + " (" +
                     (result.unit.empty() ? "a plain number" : result.unit) + ")")
        .at(reference.origin);
  }
  return reference.value / unit.value;
}

}  // namespace bushel
