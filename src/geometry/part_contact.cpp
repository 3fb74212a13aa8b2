#include "bushel/geometry/part_contact.hpp"

#include <algorithm>
#include <cmath>

namespace bushel {
namespace {

struct Offer {
  PartTouch touch;
  bool on_rim;
};

// The offer of one face, if it touches.
bool offer(const Face& face, std::uint32_t f, const Vec3& p, double r, Offer& o) {
  const FacePoint fp = nearest(face, p);
  if (!(fp.distance < r)) return false;
  if (face.kind == FaceKind::half_space) {  // any depth: the centre may lie below the plane
    o = {{fp.point, {0, 0, -1}, r - fp.distance, f}, false};
    return true;
  }
  if (fp.distance == 0.0 || !side_allows(face, fp.front_side)) return false;
  o = {{fp.point, (fp.point - p) / fp.distance, r - fp.distance, f}, fp.on_rim};
  return true;
}

// Inside before rim, deeper before shallower, then the face index.
bool before(const Offer& a, const Offer& b) {
  if (a.on_rim != b.on_rim) return !a.on_rim;
  if (a.touch.overlap != b.touch.overlap) return a.touch.overlap > b.touch.overlap;
  return a.touch.face < b.touch.face;
}

}  // namespace

int part_touches(std::span<const Face> faces, std::span<const std::uint32_t> candidates, const Vec3& p, double r,
                 std::array<PartTouch, max_part_touches>& out, std::span<const double> distances, double moved) {
  if (candidates.size() == 1) {  // the common case: a plane, a cylinder band, one facet
    Offer o;
    if (!offer(faces[candidates[0]], candidates[0], p, r, o)) return 0;
    out[0] = o.touch;
    return 1;
  }
  // A touch spans a patch of radius sqrt(2 r overlap), a few triangles even on a fine mesh:
  // when more faces offer, the best offers are kept.
  constexpr int capacity = 32;
  Offer offers[capacity];  // NOLINT: filled before use
  int n = 0;
  // The distance to a face changes by at most `moved` since the list was made.
  const bool bounded = !distances.empty();
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (bounded && distances[k] - moved >= r) continue;
    const std::uint32_t f = candidates[k];
    Offer o;
    if (!offer(faces[f], f, p, r, o)) continue;
    if (n < capacity) {
      offers[n++] = o;
    } else {
      Offer* worst = std::max_element(offers, offers + capacity, before);
      if (before(o, *worst)) *worst = o;
    }
  }
  std::sort(offers, offers + n, before);
  const double on_surface = 1e-6 * r;
  int kept = 0;
  for (int i = 0; i < n && kept < max_part_touches; ++i) {
    const Offer& o = offers[i];
    bool same = false;
    for (int k = 0; k < kept && !same; ++k) {
      const PartTouch& a = out[static_cast<std::size_t>(k)];
      same = dot(a.normal, o.touch.normal) > merge_cos ||
             (o.on_rim && std::abs(surface_offset(faces[a.face], o.touch.point)) < on_surface);
    }
    if (!same) out[static_cast<std::size_t>(kept++)] = o.touch;
  }
  return kept;
}

}  // namespace bushel
