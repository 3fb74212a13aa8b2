#pragma once
// The surface of a heap or a filled cup: the height of the grain's top on rings about a
// vertical axis, and the angle of the heap from a straight line fitted to it.

#include <vector>

#include "bushel/integrate/simulation.hpp"

namespace bushel {

struct HeapProfile {
  std::vector<double> radius;  ///< ring centres [m]
  std::vector<double> height;  ///< highest point of any element over the ring [m]; NaN if empty
  double angle = 0.0;          ///< of the line fitted to height against radius, from the horizontal [rad]
};

/// Profile about the vertical axis through (cx, cy) out to `outer` [m] in `rings` rings.
HeapProfile heap_profile(const Simulation& sim, double cx, double cy, double outer, int rings);

}  // namespace bushel
