#pragma once
// Broad phase inside one part (a mesh of many triangles): a uniform grid over the part frame
// in which each face is listed in every cell its bounding box overlaps, so that a sphere
// only tests the faces near it (docs/physics.md section 5, "geometry in the broad phase").

#include <cstdint>
#include <span>
#include <vector>

#include "bushel/geometry/face.hpp"

namespace bushel {

class FaceGrid {
 public:
  FaceGrid() = default;
  /// Bins bounded faces (not a half-space). The cell size follows the faces' mean extent,
  /// with about one face per cell, and the cell count is capped; a face that would span
  /// more than 512 cells is kept in a short list that every query tests.
  explicit FaceGrid(std::span<const Face> faces);

  /// Appends the indices of faces whose bounding box comes within `reach` of p [m], each
  /// once, ascending.
  void query(const Vec3& p, double reach, std::vector<std::uint32_t>& out) const;
  std::size_t cells() const { return start_.empty() ? 0 : start_.size() - 1; }

 private:
  Vec3 lo_;
  double cell_ = 1.0;
  int n_[3] = {0, 0, 0};
  std::vector<Vec3> face_lo_, face_hi_;
  std::vector<std::uint32_t> start_, items_;  // CSR: cell -> faces
  std::vector<std::uint32_t> large_;          // faces spanning too many cells, tested by every query
};

}  // namespace bushel
