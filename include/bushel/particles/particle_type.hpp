#pragma once

#include <string>

#include "bushel/particles/material.hpp"
#include "bushel/particles/particle_template.hpp"

namespace bushel {

/// A kind of particle in a simulation: a shape and the material it is made of. Each type is
/// one contact species, so the pair table can give each pair of types its own parameters.
struct ParticleType {
  std::string name;                                             ///< e.g. "large"; keys the contact pair table
  ParticleTemplate shape;                                       ///< sphere or clump, principal frame [m]
  Material material;                                            ///< elastic properties and density
  double mass() const { return shape.mass(material.density); }  ///< [kg]
};

}  // namespace bushel
