#include "bushel/sensors/region_sensor.hpp"

#include <algorithm>
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
      out.mass += ps.mass[b];
      out.mass_fraction[ps.body_type[b]] += ps.mass[b];
      solid += ps.mass[b] / type.material.density;
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
    exact_mass += ps.mass[b] * in / all;
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
  return out;
}

}  // namespace bushel
