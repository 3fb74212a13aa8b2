#pragma once
// Contact parameters per pair: restitution, static friction and rolling friction, looked up
// by pair of particle types or of materials. The 5-sphere wheat model needs one set per
// pair of materials (wheat-wheat, wheat-steel); the single-sphere model needs a set per pair
// of size fractions (large-large, large-medium, ...), hence lookups by particle type first.

#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bushel/contact/species_matrix.hpp"

namespace bushel {

struct ContactParameters {
  double restitution = 0.5;       ///< coefficient of restitution e [-], in (0, 1]
  double static_friction = 0.5;   ///< Coulomb static friction coefficient mu_s [-], >= 0
  double rolling_friction = 0.0;  ///< rolling friction coefficient mu_r [-], >= 0
  friend bool operator==(const ContactParameters&, const ContactParameters&) = default;
};

/// Throws InputError (keyed by field) unless 0 < e <= 1, mu_s >= 0, mu_r >= 0.
void validate(const ContactParameters& p);

/// What one side of a contact is: its particle type (empty for a wall) and its material.
struct Species {
  std::string type;      ///< particle type name; empty for geometry
  std::string material;  ///< material name
};

/// Contact parameters resolved for a fixed list of species, indexed in the hot loop.
using DenseContactTable = SpeciesMatrix<ContactParameters>;

class ContactTable {
 public:
  explicit ContactTable(ContactParameters defaults = {});

  /// Sets the parameters for the unordered pair (a, b); a and b name particle types or
  /// materials. Validates `p`.
  void set(const std::string& a, const std::string& b, const ContactParameters& p);

  /// The parameters for a contact between `a` and `b`, by precedence: the pair of particle
  /// types; a particle type of one side with the material of the other; the pair of
  /// materials; the defaults. Throws InputError if both type-material mixes are set and differ.
  const ContactParameters& lookup(const Species& a, const Species& b) const;

  /// Resolves every pair of `species` once, for O(1) indexed lookup in the time step.
  DenseContactTable resolve(std::span<const Species> species) const;

  const ContactParameters& defaults() const { return defaults_; }

 private:
  using Key = std::pair<std::string, std::string>;
  static Key key(const std::string& a, const std::string& b);
  const ContactParameters* find(const std::string& a, const std::string& b) const;

  ContactParameters defaults_;
  std::map<Key, ContactParameters> pairs_;
};

}  // namespace bushel
