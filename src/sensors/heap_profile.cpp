#include "bushel/sensors/heap_profile.hpp"

#include <cmath>
#include <limits>

namespace bushel {

HeapProfile heap_profile(const Simulation& sim, double cx, double cy, double outer, int rings) {
  const ParticleSystem& ps = sim.particles();
  const auto n = static_cast<std::size_t>(rings);
  const double width = outer / rings;
  HeapProfile out;
  out.height.assign(n, -std::numeric_limits<double>::infinity());
  for (std::size_t k = 0; k < n; ++k) out.radius.push_back((static_cast<double>(k) + 0.5) * width);
  for (std::size_t s = 0; s < ps.spheres(); ++s) {
    const Vec3& x = ps.sphere_position[s];
    const double r = std::hypot(x.x - cx, x.y - cy);
    if (r >= outer) continue;
    auto& h = out.height[static_cast<std::size_t>(r / width)];
    h = std::max(h, x.z + ps.radius[s]);
  }
  // Least squares of height on radius over the rings that hold grain.
  double sr = 0.0, sh = 0.0, srr = 0.0, srh = 0.0, m = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(out.height[k])) {
      out.height[k] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    const double r = out.radius[k], h = out.height[k];
    sr += r, sh += h, srr += r * r, srh += r * h, m += 1.0;
  }
  const double den = m * srr - sr * sr;
  out.angle = m >= 2.0 && den > 0.0 ? std::atan(std::abs((m * srh - sr * sh) / den)) : 0.0;
  return out;
}

}  // namespace bushel
