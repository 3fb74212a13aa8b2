#pragma once

#include "bushel/core/vec3.hpp"

namespace bushel {

/// One sphere of a particle template, in the template's body frame.
struct SphereElement {
  Vec3 centre;          ///< centre in the body frame [m]
  double radius = 0.0;  ///< [m]
};

}  // namespace bushel
