#pragma once
// Arithmetic on quantities with units, for scenario files: "${cup_height + outlet_gap}",
// "${(top_diameter - outlet_diameter) / 2 * tan(wall_angle)}", and the results a scenario
// computes from its stages' values. Every operand carries its dimension, so a sum of a length
// and a time is an error, and the result is written in SI with its unit ("0.1524 m").
//
// Grammar: sums and differences of products and quotients of factors; a factor is a number
// with an optional unit ("5.1 cm", "2", "50%"), a name, a parenthesised expression, a unary
// minus, or a function of one argument: sqrt, abs, sin, cos, tan (of an angle or a plain
// number in radians); `pi` is a name of its own.

#include <functional>
#include <string>
#include <string_view>

#include "bushel/units/units.hpp"

namespace bushel::units {

/// A value in SI with its dimension.
struct Quantity {
  double value = 0.0;  ///< [SI]
  Dimension dimension;
};

/// Resolves a name (letters, digits, '_' and '.') to its quantity; throws InputError if
/// the name is unknown (with the names it knows).
using NameLookup = std::function<Quantity(const std::string&)>;

/// Evaluates an expression; throws InputError naming the expression and what was wrong.
Quantity evaluate(std::string_view expression, const NameLookup& lookup);

/// Parses "101.6 mm", "2" or "50%" as a quantity of any dimension; throws InputError.
Quantity parse_quantity(std::string_view text);

/// The SI unit symbol of a dimension ("m", "kg/m3", "" for plain numbers); throws
/// InputError if bushel has no unit of that dimension.
std::string_view si_symbol(Dimension d);

/// "0.1524 m": the value to 12 significant digits and its SI unit.
std::string format_si(const Quantity& q);

}  // namespace bushel::units
