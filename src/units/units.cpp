#include "bushel/units/units.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>

#include "bushel/core/did_you_mean.hpp"
#include "bushel/core/input_error.hpp"

namespace bushel::units {
namespace {

// US (Winchester) bushel, 2150.42 cubic inches; 1 lb/bu = 12.8718 kg/m3.
constexpr double bushel_m3 = 0.03523907016688;
constexpr double pound_kg = 0.45359237;
constexpr double deg = std::numbers::pi / 180.0;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::string accepted_units(Dimension d) {
  std::string out;
  for (const auto& u : known_units()) {
    if (u.dimension != d) continue;
    out += out.empty() ? "" : ", ";
    out += u.symbol;
  }
  return out;
}

// Splits "6.12 mm" into the number and the rest; throws if there is no number.
std::pair<double, std::string_view> split_number(std::string_view text) {
  const std::string_view s = trim(text);
  double value = 0.0;
  const char* first = s.data();
  if (!s.empty() && s.front() == '+') ++first;  // from_chars rejects a leading '+'
  const auto [end, ec] = std::from_chars(first, s.data() + s.size(), value);
  if (ec != std::errc{} || first == s.data() + s.size()) {
    throw InputError("expected a number, got '" + std::string(text) + "'");
  }
  if (!std::isfinite(value)) throw InputError("expected a finite number, got '" + std::string(text) + "'");
  return {value, trim(std::string_view(end, static_cast<std::size_t>(s.data() + s.size() - end)))};
}

}  // namespace

const std::vector<Unit>& known_units() {
  static const std::vector<Unit> table = {
      {"m", 1.0, dim::length},
      {"cm", 1e-2, dim::length},
      {"mm", 1e-3, dim::length},
      {"um", 1e-6, dim::length},
      {"in", 0.0254, dim::length},
      {"ft", 0.3048, dim::length},
      {"m2", 1.0, dim::area},
      {"cm2", 1e-4, dim::area},
      {"mm2", 1e-6, dim::area},
      {"m3", 1.0, dim::volume},
      {"L", 1e-3, dim::volume},
      {"mL", 1e-6, dim::volume},
      {"cm3", 1e-6, dim::volume},
      {"mm3", 1e-9, dim::volume},
      {"bu", bushel_m3, dim::volume},
      {"kg", 1.0, dim::mass},
      {"g", 1e-3, dim::mass},
      {"mg", 1e-6, dim::mass},
      {"t", 1e3, dim::mass},
      {"lb", pound_kg, dim::mass},
      {"s", 1.0, dim::time},
      {"ms", 1e-3, dim::time},
      {"us", 1e-6, dim::time},
      {"min", 60.0, dim::time},
      {"h", 3600.0, dim::time},
      {"Hz", 1.0, dim::frequency},
      {"/s", 1.0, dim::frequency},  // a rate of events: "500 /s" particles per second
      {"m/s", 1.0, dim::velocity},
      {"cm/s", 1e-2, dim::velocity},
      {"mm/s", 1e-3, dim::velocity},
      {"m/s2", 1.0, dim::acceleration},
      {"kg/m3", 1.0, dim::density},
      {"g/cm3", 1e3, dim::density},
      {"lb/bu", pound_kg / bushel_m3, dim::density},
      {"kg/s", 1.0, dim::mass_flow},
      {"g/s", 1e-3, dim::mass_flow},
      {"J", 1.0, dim::energy},
      {"mJ", 1e-3, dim::energy},
      {"uJ", 1e-6, dim::energy},
      {"nJ", 1e-9, dim::energy},
      {"N", 1.0, dim::force},
      {"kN", 1e3, dim::force},
      {"Pa", 1.0, dim::pressure},
      {"kPa", 1e3, dim::pressure},
      {"MPa", 1e6, dim::pressure},
      {"GPa", 1e9, dim::pressure},
      {"psi", 6894.757293168361, dim::pressure},
      {"rad", 1.0, dim::angle},
      {"deg", deg, dim::angle},
      {"rad/s", 1.0, dim::angular_velocity},
      {"deg/s", deg, dim::angular_velocity},
      {"rpm", 2.0 * std::numbers::pi / 60.0, dim::angular_velocity},
      {"%", 1e-2, dim::dimensionless},
  };
  return table;
}

std::string dimension_name(Dimension d) {
  static const std::pair<Dimension, const char*> names[] = {
      {dim::dimensionless, "dimensionless number"},
      {dim::length, "length"},
      {dim::area, "area"},
      {dim::volume, "volume"},
      {dim::mass, "mass"},
      {dim::time, "time"},
      {dim::frequency, "frequency"},
      {dim::velocity, "velocity"},
      {dim::acceleration, "acceleration"},
      {dim::density, "density"},
      {dim::mass_flow, "mass flow rate"},
      {dim::force, "force"},
      {dim::pressure, "pressure"},
      {dim::energy, "energy"},
      {dim::angle, "angle"},
      {dim::angular_velocity, "angular velocity"},
  };
  for (const auto& [dimension, name] : names) {
    if (dimension == d) return name;
  }
  return "quantity of dimension L^" + std::to_string(d.length) + " M^" + std::to_string(d.mass) + " T^" +
         std::to_string(d.time) + " A^" + std::to_string(d.angle);
}

const Unit& unit(std::string_view symbol) {
  const auto& table = known_units();
  const auto it = std::find_if(table.begin(), table.end(), [&](const Unit& u) { return u.symbol == symbol; });
  if (it != table.end()) return *it;
  std::vector<std::string> symbols;
  for (const auto& u : table) symbols.emplace_back(u.symbol);
  throw InputError("unknown unit '" + std::string(symbol) + "'" + did_you_mean(symbol, symbols));
}

double parse(std::string_view text, Dimension expected) {
  const std::string what = dimension_name(expected);
  auto fail = [&](const std::string& why) -> InputError {
    const std::string accepted = accepted_units(expected);
    const char* article = std::string_view("aeiou").find(what.front()) != std::string_view::npos ? "an " : "a ";
    return InputError(std::string("expected ") + article + what +
                      (accepted.empty() ? "" : " with a unit (" + accepted + ")") + ", got '" + std::string(text) +
                      "'" + why);
  };
  std::pair<double, std::string_view> parts;
  try {
    parts = split_number(text);
  } catch (const InputError&) {
    throw fail("");
  }
  const auto [value, symbol] = parts;
  if (symbol.empty()) {
    if (expected == dim::dimensionless) return value;
    throw fail(": the unit is missing");
  }
  const Unit* u = nullptr;
  try {
    u = &unit(symbol);
  } catch (const InputError& e) {
    throw fail(": " + e.problem());
  }
  if (u->dimension != expected) {
    throw fail(": '" + std::string(symbol) + "' is a unit of " + dimension_name(u->dimension));
  }
  return value * u->factor;
}

double parse_number(std::string_view text) {
  const auto [value, rest] = split_number(text);
  if (!rest.empty()) throw InputError("expected a plain number, got '" + std::string(text) + "'");
  return value;
}

double to_unit(double value_si, std::string_view symbol) { return value_si / unit(symbol).factor; }

double from_unit(double value, std::string_view symbol) { return value * unit(symbol).factor; }

}  // namespace bushel::units
