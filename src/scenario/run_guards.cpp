#include "bushel/scenario/run_guards.hpp"

#include <cmath>

#include <fmt/format.h>

#include "bushel/integrate/simulation.hpp"
#include "bushel/io/binary_archive.hpp"

namespace bushel {
namespace {

// The first body whose state is not finite, or whose speed or travel per step passes the
// limits; "" if none.
std::string check_bodies(const RunGuards& guards, const Simulation& sim) {
  const ParticleSystem& ps = sim.particles();
  const double dt = sim.settings().dt;
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    const Vec3 x = ps.position[b], v = ps.velocity[b], w = ps.angular_velocity[b];
    const bool finite = std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z) && std::isfinite(v.x) &&
                        std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(w.x) && std::isfinite(w.y) &&
                        std::isfinite(w.z);
    if (!finite) {
      return fmt::format(
          "particle {} has a position, velocity or spin that is not a finite number (NaN or "
          "infinite): the state has blown up",
          ps.body_id[b]);
    }
    const double speed = norm(v);
    if (speed > guards.max_speed) {
      return fmt::format(
          "particle {} moves at {:.4g} m/s, above the guard's {:g} m/s (simulation.guards.max_speed): energy grows "
          "without a source (a time step too long for the contacts, a gravity or a velocity out of range)",
          ps.body_id[b], speed, guards.max_speed);
    }
    double radius = INFINITY;
    for (std::uint32_t s = ps.first_sphere[b]; s < ps.first_sphere[b] + ps.sphere_count[b]; ++s)
      radius = std::min(radius, ps.radius[s]);
    if (speed * dt > guards.max_travel * radius) {
      return fmt::format(
          "particle {} moves {:.3g} of its radius in one step, above the guard's {:g} "
          "(simulation.guards.max_travel): it passes through walls and neighbours (a time step too long, or "
          "contacts too soft)",
          ps.body_id[b], speed * dt / radius, guards.max_travel);
    }
  }
  return "";
}

}  // namespace

void GuardClock::save(io::BinaryWriter& out) const { out.put(deep_since); }
void GuardClock::load(io::BinaryReader& in) { in.get(deep_since); }

std::string check_guards(const RunGuards& guards, GuardClock& clock, const Simulation& sim, double since,
                         double peak_overlap, const ParticleTally& tally) {
  if (std::string why = check_bodies(guards, sim); !why.empty()) return why;
  if (!std::isfinite(peak_overlap) || peak_overlap >= 1.0) {
    return fmt::format(
        "an overlap reached {:.0f} % of the smaller radius: a sphere's centre inside its neighbour or "
        "behind a wall (a part that appeared inside the grain, contacts far too soft, or a time "
        "step far too long)",
        100.0 * peak_overlap);
  }
  if (peak_overlap > guards.max_overlap) {
    if (clock.deep_since < 0.0) clock.deep_since = since;
    if (sim.time() - clock.deep_since >= guards.overlap_time) {
      return fmt::format(
          "overlaps deeper than {:.0f} % of the smaller radius (the guard's "
          "simulation.guards.max_overlap) have lasted {:.4g} s, longer than its overlap_time {:g} s "
          "(at the last check {:.0f} %): the grain is crushed into itself or into a part",
          100.0 * guards.max_overlap, sim.time() - clock.deep_since, guards.overlap_time, 100.0 * peak_overlap);
    }
  } else {
    clock.deep_since = -1.0;
  }
  if (tally.created > 0 && static_cast<double>(tally.lost) > guards.max_lost * static_cast<double>(tally.created)) {
    return fmt::format(
        "{} of the {} particles created have left the domain, more than the guard's {:.0f} % "
        "(simulation.guards.max_lost): the vessel does not hold the grain",
        tally.lost, tally.created, 100.0 * guards.max_lost);
  }
  return "";
}

}  // namespace bushel
