#pragma once
// Sinks: regions that delete the particles whose centre of mass enters them (grain that
// overflowed a cup and fell past its rim can no longer change what is measured, and costs
// time), and the domain: a box outside which particles are deleted as lost. Both count
// what they removed by particle type.

#include <string>
#include <vector>

#include "bushel/geometry/region.hpp"
#include "bushel/integrate/simulation.hpp"

namespace bushel {

struct Sink {
  std::string name;
  Region region;
  bool enabled = true;
  std::vector<std::size_t> count;  ///< removed, per particle type of the simulation
  std::vector<double> mass;        ///< [kg] per type

  std::size_t total_count() const;  ///< removed, all types together
  double total_mass() const;        ///< [kg] removed, all types together (summed in type order)
};

/// Removes the bodies inside enabled sinks (counted by the first sink that holds them) and
/// those outside `domain` (counted in `lost`), in one call to Simulation::remove_bodies.
/// Returns the number removed.
std::size_t apply_sinks(Simulation& sim, std::vector<Sink>& sinks, const Region& domain, Sink& lost);

}  // namespace bushel
