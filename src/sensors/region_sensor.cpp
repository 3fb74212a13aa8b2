#include "bushel/sensors/region_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace bushel {

RegionReading read_region(const Simulation& sim, const Region& region) {
  const ParticleSystem& ps = sim.particles();
  RegionReading out;
  out.mass_fraction.assign(ps.types().size(), 0.0);
  const double volume = region.volume();
  std::vector<std::uint8_t> is_inside(ps.bodies(), 0);
  double solid = 0.0, exact_mass = 0.0;
  const Vec3 lo = region.lo(), hi = region.hi();
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    const ParticleType& type = ps.types()[ps.body_type[b]];
    if (region.contains(ps.position[b])) {
      is_inside[b] = 1;
      ++out.count;
      out.mass += ps.mass(b);
      out.mass_fraction[ps.body_type[b]] += ps.mass(b);
      solid += ps.mass(b) / type.material.density;
    }
    // The share of the body inside, by its elements' volumes: only bodies near the region.
    const std::uint32_t s0 = ps.first_sphere[b], n = ps.sphere_count[b];
    double in = 0.0, all = 0.0;
    for (std::uint32_t s = s0; s < s0 + n; ++s) {
      const Vec3& x = ps.sphere_position[s];
      const double r = ps.radius[s], v = 4.0 / 3.0 * std::numbers::pi * r * r * r;
      all += v;
      if (x.x + r <= lo.x || x.y + r <= lo.y || x.z + r <= lo.z || x.x - r >= hi.x || x.y - r >= hi.y ||
          x.z - r >= hi.z) {
        continue;
      }
      in += region.sphere_volume_inside(x, r);
    }
    exact_mass += ps.mass(b) * in / all;
  }
  for (double& f : out.mass_fraction) f = out.mass > 0.0 ? f / out.mass : 0.0;
  out.bulk_density = out.mass / volume;
  out.bulk_density_exact = exact_mass / volume;
  out.packing_fraction = solid / volume;

  // Touching pairs of bodies (several element pairs of two clumps count once).
  std::vector<std::uint64_t> touching;
  const NeighborList& nl = sim.neighbors();
  for (std::size_t p = 0; p < nl.pairs(); ++p) {
    const std::uint32_t i = nl.first(p), j = nl.second(p);
    if (i >= ps.spheres() || j >= ps.spheres()) continue;  // (a list older than a removal)
    const double reach = ps.radius[i] + ps.radius[j];
    if (norm2(ps.sphere_position[i] - ps.sphere_position[j]) >= reach * reach) continue;
    const std::uint32_t a = std::min(ps.owner[i], ps.owner[j]), b = std::max(ps.owner[i], ps.owner[j]);
    if (is_inside[a] || is_inside[b]) touching.push_back(std::uint64_t{a} << 32 | b);
  }
  std::sort(touching.begin(), touching.end());
  touching.erase(std::unique(touching.begin(), touching.end()), touching.end());
  std::size_t ends = 0;
  for (const std::uint64_t key : touching) ends += is_inside[key >> 32] + is_inside[key & 0xffffffffu];
  out.coordination = out.count > 0 ? static_cast<double>(ends) / static_cast<double>(out.count) : 0.0;
  out.surface_margin = grain_surface_margin(sim, region);
  return out;
}

double grain_surface_margin(const Simulation& sim, const Region& region) {
  const ParticleSystem& ps = sim.particles();
  const Vec3 lo = region.lo(), hi = region.hi();
  double largest = 0.0;
  for (std::size_t s = 0; s < ps.spheres(); ++s) largest = std::max(largest, ps.radius[s]);
  if (largest == 0.0) return lo.z - hi.z;
  // Columns over the footprint's bounding square less the edge; at least one.
  const double edge = std::min(largest, 0.25 * std::min(hi.x - lo.x, hi.y - lo.y)), cell = 4.0 * largest;
  const double x0 = lo.x + edge, y0 = lo.y + edge;
  const auto nx = static_cast<std::size_t>(std::max(1.0, std::floor((hi.x - lo.x - 2.0 * edge) / cell)));
  const auto ny = static_cast<std::size_t>(std::max(1.0, std::floor((hi.y - lo.y - 2.0 * edge) / cell)));
  const double wx = std::max(hi.x - lo.x - 2.0 * edge, 0.0) / static_cast<double>(nx);
  const double wy = std::max(hi.y - lo.y - 2.0 * edge, 0.0) / static_cast<double>(ny);
  // A cylinder's columns are those wholly inside its circle less the edge (or the middle one).
  std::vector<std::uint8_t> used(nx * ny, 1);
  if (region.kind == Region::Kind::cylinder) {
    const double reach = region.radius - edge;
    bool any = false;
    for (std::size_t i = 0; i < nx; ++i) {
      for (std::size_t j = 0; j < ny; ++j) {
        const double ax = std::max(std::abs(x0 + static_cast<double>(i) * wx - region.position.x),
                                   std::abs(x0 + static_cast<double>(i + 1) * wx - region.position.x));
        const double ay = std::max(std::abs(y0 + static_cast<double>(j) * wy - region.position.y),
                                   std::abs(y0 + static_cast<double>(j + 1) * wy - region.position.y));
        used[i * ny + j] = ax * ax + ay * ay <= reach * reach;
        any = any || used[i * ny + j];
      }
    }
    if (!any) used[(nx / 2) * ny + ny / 2] = 1;
  }
  std::vector<double> top(nx * ny, lo.z);
  for (std::size_t s = 0; s < ps.spheres(); ++s) {
    const Vec3& x = ps.sphere_position[s];
    const double i = std::floor((x.x - x0) / wx), j = std::floor((x.y - y0) / wy);
    if (!(i >= 0.0 && j >= 0.0 && i < static_cast<double>(nx) && j < static_cast<double>(ny))) continue;
    const std::size_t k = static_cast<std::size_t>(i) * ny + static_cast<std::size_t>(j);
    if (x.z >= lo.z) top[k] = std::max(top[k], x.z + ps.radius[s]);
  }
  double lowest = INFINITY;
  for (std::size_t k = 0; k < top.size(); ++k)
    if (used[k]) lowest = std::min(lowest, top[k]);
  return lowest - hi.z;
}

}  // namespace bushel
