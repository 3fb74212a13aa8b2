#include "bushel/analysis/compressibility.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <utility>

#include "bushel/core/choice.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/units/units.hpp"

namespace bushel {

Extrapolation parse_extrapolation(const std::string& text) {
  return parse_choice<Extrapolation>(
      text, {{"error", Extrapolation::error}, {"hold", Extrapolation::hold}, {"linear", Extrapolation::linear}});
}

Compressibility Compressibility::none() { return {}; }

Compressibility Compressibility::wpacking(double a, double b, double c, double moisture_percent) {
  for (const auto& [value, key] : {std::pair{a, "a"}, {b, "b"}, {c, "c"}, {moisture_percent, "moisture"}}) {
    if (!std::isfinite(value)) throw InputError("expected a finite number").with_key(key);
  }
  if (moisture_percent < 0.0 || moisture_percent >= 100.0) {
    throw InputError(fmt::format("expected a moisture content in [0, 100) % wet basis, got {}%", moisture_percent))
        .with_key("moisture");
  }
  Compressibility m;
  m.kind_ = Kind::wpacking;
  m.a_ = a, m.b_ = b, m.c_ = c, m.moisture_ = moisture_percent;
  return m;
}

Compressibility Compressibility::table(std::vector<double> pressure, std::vector<double> ratio, Extrapolation beyond,
                                       std::string source) {
  auto fail = [&](const std::string& problem) { return InputError(problem).at(source); };
  if (pressure.empty() || pressure.size() != ratio.size()) throw fail("expected a table of at least one row");
  if (pressure.front() != 0.0) {
    throw fail(fmt::format("expected the first row at 0 Pa (the uncompacted density), got {} Pa", pressure.front()));
  }
  for (std::size_t i = 0; i < pressure.size(); ++i) {
    if (!(ratio[i] > 0.0) || !std::isfinite(ratio[i]))
      throw fail(fmt::format("expected a positive ratio in row {}", i + 1));
    if (i > 0 && !(pressure[i] > pressure[i - 1])) {
      throw fail(fmt::format("expected pressures increasing down the table; row {} has {} Pa after {} Pa", i + 1,
                             pressure[i], pressure[i - 1]));
    }
  }
  Compressibility m;
  m.kind_ = Kind::table;
  m.beyond_ = beyond;
  m.source_ = std::move(source);
  // Fritsch-Carlson slopes: a cubic Hermite through the points that is monotone wherever
  // the data are (no overshoot between two levels of a compression run).
  const std::size_t n = pressure.size();
  std::vector<double> secant(n > 1 ? n - 1 : 0), slope(n, 0.0);
  for (std::size_t i = 0; i + 1 < n; ++i) secant[i] = (ratio[i + 1] - ratio[i]) / (pressure[i + 1] - pressure[i]);
  if (n > 1) {
    slope[0] = secant[0];
    slope[n - 1] = secant[n - 2];
    for (std::size_t i = 1; i + 1 < n; ++i) {
      slope[i] = secant[i - 1] * secant[i] <= 0.0 ? 0.0 : 0.5 * (secant[i - 1] + secant[i]);
    }
    for (std::size_t i = 0; i + 1 < n; ++i) {
      if (secant[i] == 0.0) {
        slope[i] = slope[i + 1] = 0.0;
        continue;
      }
      const double alpha = slope[i] / secant[i], beta = slope[i + 1] / secant[i];
      const double s = alpha * alpha + beta * beta;
      if (s > 9.0) {  // outside the monotonicity region: scale both back onto its edge
        const double tau = 3.0 / std::sqrt(s);
        slope[i] = tau * alpha * secant[i];
        slope[i + 1] = tau * beta * secant[i];
      }
    }
  }
  m.pressure_ = std::move(pressure);
  m.ratio_ = std::move(ratio);
  m.slope_ = std::move(slope);
  return m;
}

Compressibility Compressibility::read_csv(const std::string& path, Extrapolation beyond) {
  const io::CsvTable t = io::CsvTable::read(path);
  const std::size_t cp = t.column("pressure");
  const bool densities = t.has_column("bulk_density");
  if (!densities && !t.has_column("packing_ratio")) {
    throw InputError("expected a column bulk_density or packing_ratio").at(path).with_key("header");
  }
  const std::size_t cv = t.column(densities ? "bulk_density" : "packing_ratio");
  std::vector<double> pressure, value;
  for (const io::CsvRow& row : t.rows()) {
    auto field = [&](std::size_t c, units::Dimension d, const char* name) {
      try {
        return units::parse(row.fields[c], d);
      } catch (const InputError& e) {
        throw e.at(path, row.line).with_key(name);
      }
    };
    pressure.push_back(field(cp, units::dim::pressure, "pressure"));
    value.push_back(densities ? field(cv, units::dim::density, "bulk_density")
                              : field(cv, units::dim::dimensionless, "packing_ratio"));
  }
  return densities ? density_table(std::move(pressure), std::move(value), beyond, path)
                   : table(std::move(pressure), std::move(value), beyond, path);
}

Compressibility Compressibility::density_table(std::vector<double> pressure, std::vector<double> density,
                                               Extrapolation beyond, std::string source) {
  if (!density.empty() && density.front() > 0.0) {
    const double d0 = density.front();
    for (double& v : density) v /= d0;
  }
  return table(std::move(pressure), std::move(density), beyond, std::move(source));
}

double Compressibility::table_ratio(double p) const {
  const std::size_t n = pressure_.size();
  if (n == 1) return ratio_[0];
  const double lo = pressure_.front(), hi = pressure_.back();
  if (p > hi) {
    switch (beyond_) {
      case Extrapolation::hold:
        return ratio_.back();
      case Extrapolation::linear:
        return ratio_[n - 1] + (ratio_[n - 1] - ratio_[n - 2]) / (pressure_[n - 1] - pressure_[n - 2]) * (p - hi);
      case Extrapolation::error:
        throw InputError(fmt::format("the pressure reaches {:.4g} kPa, beyond the table's {:.4g} to {:.4g} kPa; "
                                     "extend the table, or choose --extrapolate hold or linear",
                                     p * 1e-3, lo * 1e-3, hi * 1e-3))
            .at(source_);
    }
  }
  // The interval holding p, then the cubic Hermite on it.
  const auto it = std::upper_bound(pressure_.begin(), pressure_.end(), p);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(it - pressure_.begin()), n - 1) - 1;
  const double h = pressure_[i + 1] - pressure_[i], t = (p - pressure_[i]) / h;
  const double t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * ratio_[i] + (t3 - 2 * t2 + t) * h * slope_[i] + (-2 * t3 + 3 * t2) * ratio_[i + 1] +
         (t3 - t2) * h * slope_[i + 1];
}

double Compressibility::density(double pressure, double initial_density) const {
  if (!(pressure >= 0.0)) throw InputError(fmt::format("expected a pressure >= 0, got {} Pa", pressure));
  double d = initial_density;
  switch (kind_) {
    case Kind::none:
      break;
    case Kind::wpacking: {
      const double p = pressure * 1e-3;  // the form's pressure unit, kPa
      d = initial_density + a_ * p + b_ * std::sqrt(p) + c_ * p * moisture_;
      break;
    }
    case Kind::table:
      d = initial_density * table_ratio(pressure);
      break;
  }
  if (!(d > 0.0)) {
    throw InputError(fmt::format("the compressibility model gives a bulk density of {:.4g} kg/m3 at {:.4g} kPa", d,
                                 pressure * 1e-3));
  }
  return d;
}

std::string Compressibility::describe() const {
  switch (kind_) {
    case Kind::none:
      return "none (bulk density independent of pressure)";
    case Kind::wpacking:
      return fmt::format("WPACKING: D - D_o = {} P + {} sqrt(P) + {} P MC (P in kPa, D in kg/m3), MC = {}%", a_, b_, c_,
                         moisture_);
    case Kind::table:
      return fmt::format("table {} ({} rows, 0 to {:.4g} kPa, beyond: {})", source_, pressure_.size(),
                         pressure_.back() * 1e-3,
                         beyond_ == Extrapolation::error  ? "error"
                         : beyond_ == Extrapolation::hold ? "hold"
                                                          : "linear");
  }
  return {};
}

}  // namespace bushel
