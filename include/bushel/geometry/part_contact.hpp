#pragma once
// The contacts of one sphere with one part (docs/physics.md section 6). Each nearby face offers
// its nearest point; the offers are merged so that one touch of the surface is one contact:
//   - offers inside a face come before offers on a rim (edge or vertex), deeper before
//     shallower (then by face index, so the result is deterministic);
//   - an offer is dropped when its normal lies within merge_angle of a contact already kept
//     (the same touch seen from a neighbouring triangle, or from the next facet of a finely
//     tessellated curved wall);
//   - a rim offer is dropped when its point lies on the surface of a face already kept (a
//     sphere on triangle A also "touches" the shared edge of its coplanar neighbour B).
// So a sphere on a flat mesh gets one contact wherever it sits (face, edge or vertex) and a
// sphere in a corner gets one per wall. At most max_part_touches are kept.

#include <array>
#include <cstdint>
#include <span>

#include "bushel/geometry/face.hpp"

namespace bushel {

inline constexpr int max_part_touches = 3;
/// Offers whose normals are closer than this are one contact (20 degrees) [-].
inline constexpr double merge_cos = 0.9396926207859084;

struct PartTouch {
  Vec3 point;              ///< contact point, part frame [m]
  Vec3 normal;             ///< unit, from the sphere's centre towards the surface
  double overlap = 0.0;    ///< [m]
  std::uint32_t face = 0;  ///< index of the face that gave it
};

/// Contacts of the sphere (centre p in the part frame, radius r) with the faces listed in
/// `candidates`; returns how many were written to `out`. If `distances` is given (one per
/// candidate: the centre's distance from the face when the list was made [m]) and the
/// sphere and part have together moved at most `moved` [m] since, faces that cannot be
/// within r are skipped without a nearest-point test.
int part_touches(std::span<const Face> faces, std::span<const std::uint32_t> candidates, const Vec3& p, double r,
                 std::array<PartTouch, max_part_touches>& out, std::span<const double> distances = {},
                 double moved = 0.0);

}  // namespace bushel
