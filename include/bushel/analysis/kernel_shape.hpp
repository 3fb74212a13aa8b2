#pragma once
// Kernel shape factors from the three principal dimensions (docs/wheat.md, "Formulas the program
// offers users"; Mohsenin, Physical Properties of Plant and Animal Materials).

namespace bushel {

/// The three orthogonal dimensions of a kernel, any one length unit, length >= width >= thickness.
struct KernelDimensions {
  double length = 0.0;     ///< l, the longest dimension
  double width = 0.0;      ///< w
  double thickness = 0.0;  ///< t, the shortest dimension
};

struct ShapeFactors {
  double equivalent_diameter = 0.0;  ///< geometric mean d_s = (l w t)^(1/3), in the unit of the input
  double sphericity_mohsenin = 0.0;  ///< d_s / l [-]
  double sphericity_wadell = 0.0;    ///< surface of the equal-volume sphere / surface of the ellipsoid [-]
  double flatness = 0.0;             ///< w / t [-]
  double elongation = 0.0;           ///< l / t [-]
};

/// Wadell's sphericity uses Thomsen's approximation of the ellipsoid's surface (p = 1.6075):
///   psi = (l w t)^(2/3) / [((l w)^p + (l t)^p + (w t)^p) / 3]^(1/p).
/// Throws InputError unless all three dimensions are positive.
ShapeFactors shape_factors(const KernelDimensions& d);

}  // namespace bushel
