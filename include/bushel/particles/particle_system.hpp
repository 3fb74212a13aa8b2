#pragma once
// The particle store: rigid bodies (spheres and clumps) and their sphere elements, in
// structure-of-arrays form (one array per field, so that the hot loops stream and vectorise).
// A body owns a contiguous run of sphere elements; every element records its owner body, so
// contacts work on elements and forces are summed onto owners. Arrays are reordered by spatial sorting, so each body
// and each element also carries a stable id that never changes.

#include <cstdint>
#include <span>
#include <vector>

#include "bushel/core/mat3.hpp"
#include "bushel/core/quat.hpp"
#include "bushel/core/vec3.hpp"
#include "bushel/io/archive_fwd.hpp"
#include "bushel/particles/particle_type.hpp"

namespace bushel {

struct BodyState {
  Vec3 position;          ///< centre of mass [m]
  Quat orientation;       ///< principal frame -> world
  Vec3 velocity;          ///< [m/s]
  Vec3 angular_velocity;  ///< world frame [rad/s]
};

class ParticleSystem {
 public:
  /// Registers a type; returns its index (its contact species). Validates the material.
  std::uint32_t add_type(ParticleType type);
  /// Adds a body of `type`; returns its stable id.
  std::uint32_t add(std::uint32_t type, const BodyState& state);

  std::size_t bodies() const { return body_id.size(); }
  /// Whether the bodies keep an orientation and an angular momentum: from the first type of
  /// more than one element on. Without one, every body is a lone sphere, whose orientation
  /// changes nothing (it is not advanced) and whose angular momentum is I omega: neither is
  /// stored (56 B a body), and orientation_of and angular_momentum_of derive them.
  bool keeps_rotation() const { return keeps_rotation_; }
  /// Body b's orientation (principal frame -> world); identity where it is not kept.
  Quat orientation_of(std::size_t b) const { return keeps_rotation_ ? orientation[b] : Quat{}; }
  /// Body b's spin angular momentum, world frame [kg m2/s]; I omega where it is not kept.
  Vec3 angular_momentum_of(std::size_t b) const {
    return keeps_rotation_ ? angular_momentum[b] : inertia(b).x * angular_velocity[b];
  }
  /// Every body's orientation_of and angular_momentum_of, kept or derived (for checkpoints
  /// and state hashes, which hold them either way).
  std::vector<Quat> orientations() const;
  std::vector<Vec3> angular_momenta() const;
  std::size_t spheres() const { return sphere_id.size(); }
  const std::vector<ParticleType>& types() const { return types_; }

  /// World positions of all sphere elements from the body poses.
  void update_sphere_positions();
  /// World positions of body b's elements from its pose: a lone sphere sits at its centre of
  /// mass (as the contact law assumes); a clump's elements turn with one rotation matrix.
  /// `placed(s, position)` is called for each element as it is placed.
  template <class Placed>
  void place_elements(std::size_t b, Placed&& placed) {
    if (sphere_count[b] == 1) {
      const std::uint32_t s = first_sphere[b];
      sphere_position[s] = position[b];
      placed(s, position[b]);
      return;
    }
    place_elements(b, to_matrix(orientation[b]), placed);  // (a clump: kept)
  }
  /// The same for a clump whose rotation matrix r (of its orientation) is at hand.
  template <class Placed>
  void place_elements(std::size_t b, const Mat3& r, Placed&& placed) {
    const std::uint32_t s0 = first_sphere[b], n = sphere_count[b];
    const Vec3* const centre = offsets(b).data();
    const Vec3 x = position[b];
    for (std::uint32_t k = 0; k < n; ++k) {
      const Vec3 p = x + r * centre[k];
      sphere_position[s0 + k] = p;
      placed(s0 + k, p);
    }
  }

  // What every body of a type shares is kept once per type: a lone sphere's store is its
  // motion and its element. (A body's force and torque of the last step live with the
  // engine's contact sums: Simulation::body_force.)
  /// Mass of body b [kg].
  double mass(std::size_t b) const { return type_mass_[body_type[b]]; }
  /// Masses per type [kg] (index: body_type, or an element's species).
  std::span<const double> type_mass() const { return type_mass_; }
  /// Principal moments of body b [kg m2].
  const Vec3& inertia(std::size_t b) const { return type_inertia_[body_type[b]]; }
  /// Their inverses [1/(kg m2)], so the step multiplies.
  const Vec3& inverse_inertia(std::size_t b) const { return type_inverse_inertia_[body_type[b]]; }
  /// Principal moments per type [kg m2] (index: body_type, or an element's species).
  std::span<const Vec3> type_inertia() const { return type_inertia_; }
  /// Their inverses per type [1/(kg m2)].
  std::span<const Vec3> type_inverse_inertia() const { return type_inverse_inertia_; }
  /// Centres of body b's elements in its principal frame [m], in element order.
  std::span<const Vec3> offsets(std::size_t b) const {
    return std::span<const Vec3>(type_offsets_).subspan(type_first_offset_[body_type[b]], sphere_count[b]);
  }
  /// Reorders bodies (and their elements, contiguously) to `order` (new index -> old index);
  /// bodies missing from `order` are dropped.
  /// Returns the sphere permutation applied (new sphere index -> old sphere index).
  std::vector<std::uint32_t> permute(std::span<const std::uint32_t> order);

  /// What a checkpoint section of version 1 or 2 also held per body, which version 3 leaves to
  /// the engine's contact sums: the last step's total force [N], torque [N m] and CDT rolling
  /// resistance [N m].
  struct SavedForces {
    std::vector<Vec3> force, torque;
    std::vector<double> rolling_resistance;
  };
  /// Every body and element (not the types), for a checkpoint; `load` restores them exactly
  /// into a system with the same types (throws InputError otherwise).
  void save(io::BinaryWriter& out) const;
  /// `version` of the section: version 1 also held each body's moments and each element's
  /// centre, versions 1 and 2 each body's mass and last forces (returned; empty for version
  /// 3). Masses, radii (and those) must be the types' (throws InputError otherwise).
  SavedForces load(io::BinaryReader& in, std::uint32_t version);

  /// Translational plus rotational kinetic energy [J].
  double kinetic_energy() const;
  /// Rotational kinetic energy of one body [J], with its principal inertia.
  double rotational_energy(std::size_t b) const;
  /// Spin angular momentum of one body in the world frame [kg m2/s].
  Vec3 spin_momentum(std::size_t b) const;

  // --- bodies (index b) -------------------------------------------------------------------
  std::vector<std::uint32_t> body_id;       ///< stable id
  std::vector<std::uint32_t> body_type;     ///< index into types()
  std::vector<Vec3> position;               ///< centre of mass [m]
  std::vector<Quat> orientation;            ///< principal frame -> world; not advanced for a lone sphere (no
                                            ///< effect); empty unless keeps_rotation()
  std::vector<Vec3> velocity;               ///< [m/s]
  std::vector<Vec3> angular_velocity;       ///< world frame [rad/s]; a clump's is derived from angular_momentum
                                            ///< each step, a sphere's is its rotational state
  std::vector<Vec3> angular_momentum;       ///< spin angular momentum, world frame [kg m2/s]: a clump's
                                            ///< rotational state; empty unless keeps_rotation()
  std::vector<std::uint32_t> first_sphere;  ///< index of the body's first element
  std::vector<std::uint32_t> sphere_count;  ///< number of elements

  // --- sphere elements (index s) ----------------------------------------------------------
  std::vector<std::uint32_t> sphere_id;  ///< stable id
  std::vector<std::uint32_t> owner;      ///< body index
  std::vector<std::uint32_t> species;    ///< contact species (= the owner's body_type)
  std::vector<double> radius;            ///< [m]
  std::vector<Vec3> sphere_position;     ///< world centre, refreshed each step [m]

 private:
  // The loaded bodies' masses and elements' radii against their types' (a scenario whose
  // types changed since the checkpoint), and `with_moments` (version 1) the saved moments and
  // centres too.
  void check_type_shapes(std::span<const double> masses, bool with_moments, std::span<const Vec3> moments,
                         std::span<const Vec3> inverse_moments, std::span<const Vec3> centres) const;

  std::vector<ParticleType> types_;
  std::vector<double> type_mass_;                          // per type [kg]
  std::vector<Vec3> type_inertia_, type_inverse_inertia_;  // per type [kg m2], [1/(kg m2)]
  std::vector<Vec3> type_offsets_;                         // the types' element centres, type by type [m]
  std::vector<std::uint32_t> type_first_offset_;           // a type's first in type_offsets_
  bool keeps_rotation_ = false;
  std::uint32_t next_body_id_ = 0;
  std::uint32_t next_sphere_id_ = 0;
};

}  // namespace bushel
