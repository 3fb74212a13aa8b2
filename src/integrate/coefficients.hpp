#pragma once
// The contact-law coefficients of every pair of species: the particle types, then the parts.

#include <vector>

#include "bushel/contact/contact_table.hpp"
#include "bushel/contact/pair_coefficients.hpp"
#include "bushel/geometry/part.hpp"
#include "bushel/particles/particle_type.hpp"

namespace bushel::engine {

PairCoefficientTable make_coefficients(const ContactTable& table, const std::vector<ParticleType>& types,
                                       const std::vector<Part>& parts);

}  // namespace bushel::engine
