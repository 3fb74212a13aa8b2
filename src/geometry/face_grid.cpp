#include "bushel/geometry/face_grid.hpp"

#include <algorithm>
#include <cmath>

#include "bushel/core/input_error.hpp"

namespace bushel {

FaceGrid::FaceGrid(std::span<const Face> faces) {
  const std::size_t n = faces.size();
  face_lo_.resize(n);
  face_hi_.resize(n);
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  double extent = 0.0;
  for (std::size_t f = 0; f < n; ++f) {
    if (faces[f].kind == FaceKind::half_space) throw InputError("a face grid cannot hold a half-space");
    bounds(faces[f], face_lo_[f], face_hi_[f]);
    lo = min(lo, face_lo_[f]);
    hi = max(hi, face_hi_[f]);
    const Vec3 e = face_hi_[f] - face_lo_[f];
    extent += std::max({e.x, e.y, e.z});
  }
  if (n == 0) return;
  const Vec3 size = hi - lo;
  // About one face per cell, never finer than the faces themselves, at most 2^22 cells.
  const double volume_cell =
      std::max(size.x, 1e-9) * std::max(size.y, 1e-9) * std::max(size.z, 1e-9) / static_cast<double>(n);
  cell_ = std::max({std::cbrt(volume_cell), extent / static_cast<double>(n), 1e-9});
  auto count = [&](double s) { return std::max(1, static_cast<int>(std::ceil(s / cell_))); };
  while (static_cast<double>(count(size.x)) * count(size.y) * count(size.z) > 4194304.0) cell_ *= 1.26;
  lo_ = lo;
  n_[0] = count(size.x), n_[1] = count(size.y), n_[2] = count(size.z);
  auto cell_range = [&](const Vec3& a, const Vec3& b, int lo_i[3], int hi_i[3]) {
    const double av[3] = {a.x - lo_.x, a.y - lo_.y, a.z - lo_.z}, bv[3] = {b.x - lo_.x, b.y - lo_.y, b.z - lo_.z};
    for (int k = 0; k < 3; ++k) {
      lo_i[k] = std::clamp(static_cast<int>(std::floor(av[k] / cell_)), 0, n_[k] - 1);
      hi_i[k] = std::clamp(static_cast<int>(std::floor(bv[k] / cell_)), 0, n_[k] - 1);
    }
  };
  const std::size_t n_cells = static_cast<std::size_t>(n_[0]) * n_[1] * n_[2];
  // A face far larger than the cells (a big panel in a finely meshed part) would fill many
  // cells; it is kept apart and tested by every query instead.
  constexpr double max_cells_per_face = 512.0;
  std::vector<bool> large(n, false);
  for (std::size_t f = 0; f < n; ++f) {
    int a[3], b[3];
    cell_range(face_lo_[f], face_hi_[f], a, b);
    large[f] = static_cast<double>(b[0] - a[0] + 1) * (b[1] - a[1] + 1) * (b[2] - a[2] + 1) > max_cells_per_face;
    if (large[f]) large_.push_back(static_cast<std::uint32_t>(f));
  }
  start_.assign(n_cells + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {  // count, then fill
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    if (pass == 1) items_.resize(start_.back());
    for (std::size_t f = 0; f < n; ++f) {
      if (large[f]) continue;
      int a[3], b[3];
      cell_range(face_lo_[f], face_hi_[f], a, b);
      for (int z = a[2]; z <= b[2]; ++z) {
        for (int y = a[1]; y <= b[1]; ++y) {
          for (int x = a[0]; x <= b[0]; ++x) {
            const std::size_t c = (static_cast<std::size_t>(z) * n_[1] + y) * n_[0] + x;
            if (pass == 0) {
              ++start_[c + 1];
            } else {
              items_[fill[c]++] = static_cast<std::uint32_t>(f);
            }
          }
        }
      }
    }
    if (pass == 0) {
      for (std::size_t c = 0; c < n_cells; ++c) start_[c + 1] += start_[c];
    }
  }
}

void FaceGrid::query(const Vec3& p, double reach, std::vector<std::uint32_t>& out) const {
  if (start_.empty()) return;
  const std::size_t first = out.size();
  auto near_box = [&](std::uint32_t f) {  // distance from p to the face's box within reach
    const Vec3 &lo = face_lo_[f], &hi = face_hi_[f];
    const Vec3 d{std::max({lo.x - p.x, 0.0, p.x - hi.x}), std::max({lo.y - p.y, 0.0, p.y - hi.y}),
                 std::max({lo.z - p.z, 0.0, p.z - hi.z})};
    return norm2(d) <= reach * reach;
  };
  for (const std::uint32_t f : large_) {
    if (near_box(f)) out.push_back(f);
  }
  const double pv[3] = {p.x - lo_.x, p.y - lo_.y, p.z - lo_.z};
  int a[3], b[3];
  bool inside = true;
  for (int k = 0; k < 3; ++k) {
    const double lo = std::floor((pv[k] - reach) / cell_), hi = std::floor((pv[k] + reach) / cell_);
    if (hi < 0.0 || lo > n_[k] - 1) inside = false;  // the sphere's box misses the grid
    a[k] = static_cast<int>(std::clamp(lo, 0.0, static_cast<double>(n_[k] - 1)));
    b[k] = static_cast<int>(std::clamp(hi, 0.0, static_cast<double>(n_[k] - 1)));
  }
  for (int z = a[2]; inside && z <= b[2]; ++z) {
    for (int y = a[1]; y <= b[1]; ++y) {
      for (int x = a[0]; x <= b[0]; ++x) {
        const std::size_t c = (static_cast<std::size_t>(z) * n_[1] + y) * n_[0] + x;
        for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
          if (near_box(items_[k])) out.push_back(items_[k]);
        }
      }
    }
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
  out.erase(std::unique(out.begin() + static_cast<std::ptrdiff_t>(first), out.end()), out.end());
}

}  // namespace bushel
