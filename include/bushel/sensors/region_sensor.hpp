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
  /// The grain surface's lowest point over the region's footprint, less the region's top [m]:
  /// negative when the region is not full (its top above the surface, or above a heap's
  /// foot), so that its bulk density counts empty space. See grain_surface_margin.
  double surface_margin = 0.0;
};

/// Reads the region now. The exact variant counts, for a clump, the share of its elements'
/// volume inside (region.hpp: exact slices), times its mass.
RegionReading read_region(const Simulation& sim, const Region& region);

/// The lowest height of the grain surface over the region's footprint, less the region's top
/// [m]. The footprint (less a sphere radius at its edge, where walls stand) is cut into square
/// columns of four largest element radii; a column's surface is the highest sphere top in it
/// above the region's floor (the floor where it holds none), and the lowest column counts.
/// The highest top of a column lies up to a sphere above the mean surface, so a region whose
/// top is level with the mean surface still reads as full; a surface a sphere or more below
/// it does not.
double grain_surface_margin(const Simulation& sim, const Region& region);

}  // namespace bushel
