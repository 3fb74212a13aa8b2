#pragma once
// A triangle surface: shared vertices and triangles that index them. STL files store every
// triangle with its own three corners; reading welds equal corners into one vertex, so that
// triangles sharing an edge or a vertex are seen to share it (one contact there, not several).

#include <array>
#include <cstdint>
#include <vector>

#include "bushel/core/vec3.hpp"

namespace bushel {

struct TriangleMesh {
  std::vector<Vec3> vertices;                           ///< [m]
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< vertex indices, counter-clockwise seen from the front

  std::size_t size() const { return triangles.size(); }
  /// Corner k (0..2) of triangle t [m].
  const Vec3& corner(std::size_t t, int k) const { return vertices[triangles[t][static_cast<std::size_t>(k)]]; }
};

}  // namespace bushel
