#pragma once
// Volume and moments of the union of overlapping spheres (docs/physics.md section 1: overlaps
// are counted once). Computed once per particle template, never in the time step.
//
// Method: the union is cut into columns along x on a square grid in (y, z). Within one
// column the spheres cover a union of x-intervals, whose length and first and second x
// moments are exact; only the (y, z) integral is a midpoint sum. The error therefore comes
// from the grid in two dimensions only and falls quickly with resolution (a convergence
// test covers it).

#include <span>

#include "bushel/core/mat3.hpp"
#include "bushel/core/vec3.hpp"
#include "bushel/particles/sphere_element.hpp"

namespace bushel {

struct UnionMoments {
  double volume = 0.0;  ///< integral of dV [m3]
  Vec3 first;           ///< integral of x_i dV [m4]
  Mat3 second;          ///< integral of x_i x_j dV [m5]

  /// Centroid (centre of mass for uniform density) [m].
  Vec3 centroid() const { return first / volume; }
  /// Inertia tensor about the centroid per unit density [m5]:
  /// J_ij = integral of (|r|^2 delta_ij - r_i r_j) dV with r measured from the centroid.
  Mat3 inertia_about_centroid() const;
};

/// Integrates the union of `spheres` with `resolution` grid columns across the larger of the
/// y and z extents (the grid is square). Throws std::invalid_argument for an empty list, a
/// non-positive radius or resolution < 4. Deterministic: the same result for any number of
/// threads, since rows are summed in a fixed order.
UnionMoments integrate_union(std::span<const SphereElement> spheres, int resolution);

}  // namespace bushel
