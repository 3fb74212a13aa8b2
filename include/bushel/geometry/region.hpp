#pragma once
// A region of space: where a factory creates particles, where a sink removes them and what
// a region sensor measures. Two kinds, upright as the equipment of grain tests is: a vertical
// cylinder (its axis along z) and a box with edges along the axes.

#include <random>

#include "bushel/core/vec3.hpp"

namespace bushel {

struct Region {
  enum class Kind { cylinder, box };
  Kind kind = Kind::box;
  Vec3 position;        ///< cylinder: centre of its base; box: its centre [m]
  double radius = 0.0;  ///< cylinder [m]
  double height = 0.0;  ///< cylinder, from the base up [m]
  Vec3 size;            ///< box: edge lengths [m]

  static Region cylinder(const Vec3& base_centre, double radius, double height);
  static Region box(const Vec3& centre, const Vec3& size);

  /// Lower and upper corners of the bounding box [m].
  Vec3 lo() const;
  Vec3 hi() const;
  double volume() const;  ///< [m3]
  /// Radius of the largest sphere that fits inside [m].
  double room() const;
  bool contains(const Vec3& p) const;
  /// Whether a sphere of radius r at c lies wholly inside, with `margin` [m] to spare.
  bool contains_sphere(const Vec3& c, double r, double margin = 0.0) const;
  /// A point drawn uniformly from the region shrunk by `margin` [m] on every side.
  Vec3 sample(std::mt19937_64& rng, double margin = 0.0) const;
  /// Volume of the part of the sphere (centre c, radius r) inside the region [m3], by
  /// quadrature over horizontal slices split where the slice's shape changes (relative error
  /// below 1e-6 for the sizes of grain).
  double sphere_volume_inside(const Vec3& c, double r) const;
  /// Area of the region's horizontal section within the disc of radius a at (cx, cy) [m2].
  double section_area_in_disc(double cx, double cy, double a) const;
};

}  // namespace bushel
