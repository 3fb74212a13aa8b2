#pragma once
// How stored grain densifies under the weight above it: bulk density as a function of the
// vertical (overburden) pressure, D(P), for the bin model (bin_model.hpp). Three sources:
//  - the WPACKING form (docs/wheat.md, "Formulas the program offers users"),
//      D - D_o = a P + b sqrt(P) + c P MC,
//    with P in kPa, D in kg/m3 and MC the moisture content in % (wet basis), so a is in
//    kg/m3 per kPa, b in kg/m3 per sqrt(kPa) and c in kg/m3 per kPa per % moisture;
//  - a table of bulk density (or packing ratio) against pressure, for example the levels
//    of a compression run (experiment 3), used as the ratio D(P)/D(0) applied to the bin's
//    own initial density D_o, interpolated monotonically (Fritsch-Carlson cubic);
//  - none: D(P) = D_o.
// Outside a table's pressure range the model stops with an error unless told to hold the
// last value or to extend the end segment linearly.

#include <string>
#include <vector>

namespace bushel {

/// What a table does beyond its last (or before its first) pressure.
enum class Extrapolation {
  error,   ///< InputError naming the pressure and the table's range
  hold,    ///< the value at the end of the table
  linear,  ///< the end segment extended
};
/// "error", "hold", "linear"; throws InputError (with a did-you-mean) for anything else.
Extrapolation parse_extrapolation(const std::string& text);

class Compressibility {
 public:
  /// No compaction: D(P) = D_o.
  static Compressibility none();
  /// WPACKING: a [kg/m3/kPa], b [kg/m3/kPa^0.5], c [kg/m3/kPa/%], moisture [% wet basis].
  static Compressibility wpacking(double a, double b, double c, double moisture_percent);
  /// A table of packing ratios D(P)/D(0) at pressures [Pa], ascending from 0, each ratio
  /// > 0. `source` names the table in errors. Throws InputError for an empty table, a first
  /// pressure other than 0, pressures not strictly increasing or a non-positive ratio.
  static Compressibility table(std::vector<double> pressure, std::vector<double> ratio, Extrapolation beyond,
                               std::string source);
  /// A table of bulk densities [kg/m3] at pressures [Pa], ascending from 0: the ratios to the
  /// first density go into table() (a first density that is not positive is refused there).
  static Compressibility density_table(std::vector<double> pressure, std::vector<double> density, Extrapolation beyond,
                                       std::string source);
  /// Reads a CSV table with a column `pressure` and a column `bulk_density` (turned into
  /// ratios to the density at 0 pressure) or `packing_ratio`; every value carries its unit
  /// ("7kPa", "812.4kg/m3"; a ratio is a plain number). Errors name the file, line and column.
  static Compressibility read_csv(const std::string& path, Extrapolation beyond);

  /// Bulk density at vertical pressure `pressure` [Pa] >= 0 for initial density
  /// `initial_density` [kg/m3]. Throws InputError outside a table's range (Extrapolation::error)
  /// or if the density would not be positive.
  double density(double pressure, double initial_density) const;
  /// One line saying what the model is, for reports.
  std::string describe() const;

 private:
  enum class Kind { none, wpacking, table };
  Compressibility() = default;
  double table_ratio(double pressure) const;

  Kind kind_ = Kind::none;
  double a_ = 0.0, b_ = 0.0, c_ = 0.0, moisture_ = 0.0;  // WPACKING (kPa, kg/m3, % units)
  std::vector<double> pressure_, ratio_, slope_;         // table [Pa], [-], d ratio / dP [1/Pa]
  Extrapolation beyond_ = Extrapolation::error;
  std::string source_;
};

}  // namespace bushel
