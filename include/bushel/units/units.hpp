#pragma once
// Quantities with units at the edge of the program: everything the user types carries a
// unit suffix ("6.12mm", "22.4 MPa", "60lb/bu"); inside the engine every value is SI.
// A missing unit, an unknown unit or a unit of the wrong kind is an InputError that says
// what kind of quantity was expected and which units it accepts.

#include <string>
#include <string_view>
#include <vector>

namespace bushel::units {

/// Exponents of length, mass, time and plane angle. Angles are kept as their own
/// dimension so that "rad/s" is never accepted where "Hz" is meant, and vice versa.
struct Dimension {
  int length = 0;
  int mass = 0;
  int time = 0;
  int angle = 0;
  friend constexpr bool operator==(const Dimension&, const Dimension&) = default;
};

namespace dim {
inline constexpr Dimension dimensionless{};
inline constexpr Dimension length{1, 0, 0, 0};
inline constexpr Dimension area{2, 0, 0, 0};
inline constexpr Dimension volume{3, 0, 0, 0};
inline constexpr Dimension mass{0, 1, 0, 0};
inline constexpr Dimension time{0, 0, 1, 0};
inline constexpr Dimension frequency{0, 0, -1, 0};
inline constexpr Dimension velocity{1, 0, -1, 0};
inline constexpr Dimension acceleration{1, 0, -2, 0};
inline constexpr Dimension density{-3, 1, 0, 0};
inline constexpr Dimension mass_flow{0, 1, -1, 0};
inline constexpr Dimension force{1, 1, -2, 0};
inline constexpr Dimension pressure{-1, 1, -2, 0};
inline constexpr Dimension energy{2, 1, -2, 0};
inline constexpr Dimension angle{0, 0, 0, 1};
inline constexpr Dimension angular_velocity{0, 0, -1, 1};
}  // namespace dim

/// A unit symbol and its factor to SI: value_SI = value * factor.
struct Unit {
  std::string_view symbol;
  double factor;
  Dimension dimension;
};

/// Every unit the parser knows, in the order they are suggested in messages.
const std::vector<Unit>& known_units();

/// "length", "pressure", ... or "quantity of dimension L^a M^b T^c" for unnamed ones.
std::string dimension_name(Dimension d);

/// Parses "<number><unit>" (spaces between allowed) into SI. For `dim::dimensionless`
/// the unit may be omitted or be "%". Throws InputError on an empty or malformed number,
/// a missing unit, an unknown unit (with a did-you-mean) or a unit of another dimension.
double parse(std::string_view text, Dimension expected);

/// Parses a plain number; any trailing text (a unit, a typo) is an InputError.
double parse_number(std::string_view text);

/// Looks up a unit symbol; throws InputError if unknown.
const Unit& unit(std::string_view symbol);

/// Converts an SI value to `symbol` (e.g. to_unit(0.0346e-3, "g") == 0.0346).
double to_unit(double value_si, std::string_view symbol);

/// Converts a value in `symbol` to SI.
double from_unit(double value, std::string_view symbol);

}  // namespace bushel::units
