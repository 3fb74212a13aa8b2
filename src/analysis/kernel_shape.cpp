#include "bushel/analysis/kernel_shape.hpp"

#include <cmath>
#include "bushel/core/require.hpp"

namespace bushel {

ShapeFactors shape_factors(const KernelDimensions& d) {
  require_positive(d.length, "length", "5.42mm");
  require_positive(d.width, "width", "2.96mm");
  require_positive(d.thickness, "thickness", "2.65mm");
  constexpr double p = 1.6075;
  const double l = d.length, w = d.width, t = d.thickness;
  ShapeFactors f;
  f.equivalent_diameter = std::cbrt(l * w * t);
  f.sphericity_mohsenin = f.equivalent_diameter / l;
  const double mean_p = (std::pow(l * w, p) + std::pow(l * t, p) + std::pow(w * t, p)) / 3.0;
  f.sphericity_wadell = std::pow(l * w * t, 2.0 / 3.0) / std::pow(mean_p, 1.0 / p);
  f.flatness = w / t;
  f.elongation = l / t;
  return f;
}

}  // namespace bushel
