#pragma once
// What a region sensor measures of the particles in a region (a cup, the lower part of a
// bed): the bulk density as the trade measures it (the mass of the kernels whose centre of
// mass lies inside, over the region's volume), the exact-volume variant (the part of each
// kernel inside), composition, packing fraction and coordination number.

#include <vector>

#include "bushel/geometry/region.hpp"
#include "bushel/integrate/simulation.hpp"

namespace bushel {

struct RegionReading {
  double mass = 0.0;                  ///< of the bodies whose centre of mass is inside [kg]
  std::size_t count = 0;              ///< those bodies
  double bulk_density = 0.0;          ///< mass / region volume [kg/m3]
  double bulk_density_exact = 0.0;    ///< the part of every body inside / region volume [kg/m3]
  double packing_fraction = 0.0;      ///< solid volume of the bodies inside / region volume [-]
  double coordination = 0.0;          ///< mean number of touching particles per body inside [-]
  std::vector<double> mass_fraction;  ///< per particle type of the simulation, of `mass` [-]
};

/// Reads the region now. The exact variant counts, for a clump, the share of its elements'
/// volume inside (region.hpp: exact slices), times its mass.
RegionReading read_region(const Simulation& sim, const Region& region);

}  // namespace bushel
