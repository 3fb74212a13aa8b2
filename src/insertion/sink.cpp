#include "bushel/insertion/sink.hpp"

#include <numeric>

namespace bushel {

std::size_t Sink::total_count() const { return std::accumulate(count.begin(), count.end(), std::size_t{0}); }

double Sink::total_mass() const { return std::accumulate(mass.begin(), mass.end(), 0.0); }

std::size_t apply_sinks(Simulation& sim, std::vector<Sink>& sinks, const Region& domain, Sink& lost) {
  const ParticleSystem& ps = sim.particles();
  const std::size_t n_types = ps.types().size();
  // Every sink reports every type, removed or not.
  auto size_up = [&](Sink& s) {
    s.count.resize(n_types, 0);
    s.mass.resize(n_types, 0.0);
  };
  size_up(lost);
  for (Sink& s : sinks) size_up(s);
  auto tally = [&](Sink& s, std::size_t b) {
    ++s.count[ps.body_type[b]];
    s.mass[ps.body_type[b]] += ps.mass(b);
  };
  std::vector<std::size_t> gone;
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    const Vec3& x = ps.position[b];
    if (!domain.contains(x)) {
      tally(lost, b);
      gone.push_back(b);
      continue;
    }
    for (Sink& s : sinks) {
      if (s.enabled && s.region.contains(x)) {
        tally(s, b);
        gone.push_back(b);
        break;
      }
    }
  }
  sim.remove_bodies(gone);
  return gone.size();
}

}  // namespace bushel
