#include "bushel/particles/union_moments.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace bushel {
namespace {

// Moments of one (y, z) column: length and x-moments of the union of its x-intervals.
struct ColumnSums {
  double v = 0, x = 0, y = 0, z = 0, xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
  void add(const ColumnSums& o) {
    v += o.v, x += o.x, y += o.y, z += o.z, xx += o.xx, yy += o.yy, zz += o.zz, xy += o.xy, xz += o.xz, yz += o.yz;
  }
};

}  // namespace

Mat3 UnionMoments::inertia_about_centroid() const {
  // Parallel-axis shift of the second moments to the centroid, then J = tr(S) I - S.
  const Vec3 c = centroid();
  Mat3 s;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) s(i, j) = second(i, j) - volume * c[i] * c[j];
  }
  const double trace = s(0, 0) + s(1, 1) + s(2, 2);
  Mat3 inertia;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) inertia(i, j) = (i == j ? trace : 0.0) - s(i, j);
  }
  return inertia;
}

UnionMoments integrate_union(std::span<const SphereElement> spheres, int resolution) {
  if (spheres.empty()) throw std::invalid_argument("integrate_union: no spheres");
  if (resolution < 4) throw std::invalid_argument("integrate_union: resolution must be at least 4");
  double ylo = INFINITY, yhi = -INFINITY, zlo = INFINITY, zhi = -INFINITY;
  for (const auto& s : spheres) {
    if (!(s.radius > 0.0)) throw std::invalid_argument("integrate_union: sphere radius must be positive");
    ylo = std::min(ylo, s.centre.y - s.radius), yhi = std::max(yhi, s.centre.y + s.radius);
    zlo = std::min(zlo, s.centre.z - s.radius), zhi = std::max(zhi, s.centre.z + s.radius);
  }
  const double h = std::max(yhi - ylo, zhi - zlo) / resolution;
  const int ny = static_cast<int>(std::ceil((yhi - ylo) / h));
  const int nz = static_cast<int>(std::ceil((zhi - zlo) / h));

  std::vector<ColumnSums> rows(static_cast<std::size_t>(ny));
#pragma omp parallel
  {
    std::vector<std::pair<double, double>> intervals;
    intervals.reserve(spheres.size());
#pragma omp for schedule(static)
    for (int iy = 0; iy < ny; ++iy) {
      const double y = ylo + (iy + 0.5) * h;
      ColumnSums row;
      for (int iz = 0; iz < nz; ++iz) {
        const double z = zlo + (iz + 0.5) * h;
        intervals.clear();
        for (const auto& s : spheres) {
          const double d2 =
              s.radius * s.radius - (y - s.centre.y) * (y - s.centre.y) - (z - s.centre.z) * (z - s.centre.z);
          if (d2 <= 0.0) continue;
          const double half = std::sqrt(d2);
          intervals.emplace_back(s.centre.x - half, s.centre.x + half);
        }
        if (intervals.empty()) continue;
        std::sort(intervals.begin(), intervals.end());
        // Merge overlapping intervals and integrate 1, x, x^2 exactly over the union.
        double len = 0, m1 = 0, m2 = 0;
        auto close = [&](double a, double b) {
          len += b - a;
          m1 += 0.5 * (b * b - a * a);
          m2 += (b * b * b - a * a * a) / 3.0;
        };
        double a = intervals.front().first, b = intervals.front().second;
        for (std::size_t k = 1; k < intervals.size(); ++k) {
          if (intervals[k].first > b) {
            close(a, b);
            a = intervals[k].first;
          }
          b = std::max(b, intervals[k].second);
        }
        close(a, b);
        // y^2 and z^2 carry the cell's own spread, h^2/12, which the midpoint value misses.
        const double spread = h * h / 12.0;
        row.add({len, m1, y * len, z * len, m2, (y * y + spread) * len, (z * z + spread) * len, y * m1, z * m1,
                 y * z * len});
      }
      rows[static_cast<std::size_t>(iy)] = row;
    }
  }
  ColumnSums total;
  for (const auto& r : rows) total.add(r);  // fixed order: thread-count independent

  const double dA = h * h;
  UnionMoments out;
  out.volume = total.v * dA;
  out.first = Vec3{total.x, total.y, total.z} * dA;
  out.second = Mat3{{total.xx * dA, total.xy * dA, total.xz * dA, total.xy * dA, total.yy * dA, total.yz * dA,
                     total.xz * dA, total.yz * dA, total.zz * dA}};
  return out;
}

}  // namespace bushel
