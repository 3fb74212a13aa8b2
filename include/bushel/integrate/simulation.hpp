#pragma once
// The time stepper: particles, walls, contact laws and the neighbour list brought together
// (ARCHITECTURE.md, "Time step"). One step:
//   1. rebuild the neighbour list if needed (spatially sorting the particles every few builds)
//   2. contacts, in parallel over fixed runs of elements (each about one batch of 128
//      contacts): every element sums its own pairs (as first element) and its nearby walls;
//      the share of each pair's second element goes to the pair's slot. The contact law runs
//      over the batch at once (contact_batch.hpp).
//   3. gather onto bodies in a fixed order (thread-count independent): the elements' own
//      sums plus the slots of pairs in which they are second
//   4. integrate (symplectic Euler or velocity Verlet; quaternion rigid rotation)

#include <cstdint>
#include <string>
#include <vector>

#include "bushel/contact/contact_model.hpp"
#include "bushel/contact/contact_table.hpp"
#include "bushel/contact/neighbor_list.hpp"
#include "bushel/contact/pair_coefficients.hpp"
#include "bushel/geometry/wall.hpp"
#include "bushel/particles/particle_system.hpp"

namespace bushel {

enum class Integrator {
  symplectic_euler,  ///< v += a dt, x += v dt (EDEM)
  velocity_verlet,   ///< half kick, drift, forces, half kick
};

struct SimulationSettings {
  double dt = 0.0;                ///< time step [s]
  Vec3 gravity{0.0, 0.0, -9.81};  ///< [m/s2]
  Integrator integrator = Integrator::symplectic_euler;
  std::string rolling = "cdt";  ///< rolling model: cdt, epsd, none
  double skin = 0.0;            ///< Verlet skin [m]; 0 = 0.11 of the largest element diameter
  int sort_every = 20;          ///< spatial sort every N neighbour-list builds; 0 = never
  ContactTable contacts;        ///< restitution, friction, rolling friction per pair
};

class Simulation {
 public:
  explicit Simulation(SimulationSettings settings);

  ParticleSystem& particles() { return particles_; }
  const ParticleSystem& particles() const { return particles_; }
  /// Adds a wall; returns its index.
  std::size_t add_wall(Wall wall);
  const Wall& wall(std::size_t i) const { return walls_[i]; }
  std::size_t walls() const { return walls_.size(); }

  /// Advances `n` steps.
  void step(std::uint64_t n = 1);

  double time() const { return time_; }  ///< [s]
  std::uint64_t steps() const { return steps_; }
  const SimulationSettings& settings() const { return settings_; }
  /// Largest overlap over the radius of the smaller sphere in the last step [-].
  double max_overlap_ratio() const { return max_overlap_ratio_; }
  /// Number of sphere-sphere contacts (overlap > 0) in the last step.
  std::size_t contacts() const { return contacts_; }
  const NeighborList& neighbors() const { return neighbors_; }

 private:
  void prepare();
  void rebuild();
  void find_wall_candidates();
  void split_into_chunks();
  void spatial_sort();
  template <class Rolling>
  void compute_forces(const Rolling&);
  void compute_forces();
  void sum_wall_reactions();
  void kick(double dt);
  void drift(double dt);

  SimulationSettings settings_;
  RollingModel rolling_;
  ParticleSystem particles_;
  std::vector<Wall> walls_;
  NeighborList neighbors_;
  PairCoefficientTable coefficients_;
  std::size_t prepared_types_ = 0, prepared_walls_ = 0;
  bool forces_valid_ = false;
  int rebuild_due_ = -1;  // from the last drift: 1 yes, 0 no, -1 unknown (check every element)
  bool neighbors_configured_ = false;

  // per pair: the reaction on the second element from the last force computation
  std::vector<Vec3> pair_force_;           // force on the first element (the second gets minus this) [N]
  std::vector<Vec3> pair_torque_j_;        // torque on the second element's body [N m]
  std::vector<double> pair_cdt_j_;         // CDT magnitude on the second element's body [N m]
  std::vector<std::uint8_t> pair_active_;  // 1 while the pair touches (or may: fresh list)
  std::size_t active_build_ = 0;           // neighbour-list build the flags belong to
  // per element: its own sums over its pairs (as first element) and its walls
  std::vector<Vec3> element_force_, element_torque_;
  std::vector<double> element_cdt_;
  std::vector<std::uint32_t> chunk_start_;  // elements split into runs of about one batch of contacts
  // sphere-wall: history dense over [(s * walls + w) * h]; candidates (spheres within the
  // skin of a wall at the last build) grouped by sphere (CSR), with their results
  std::vector<double> wall_history_;
  std::vector<std::uint32_t> wall_start_, wall_of_candidate_, sphere_of_candidate_;
  std::vector<Vec3> wall_reaction_;  // [2 c]: force on the wall, its torque about the origin
  std::vector<Vec3> wall_partial_;   // per-chunk sums of wall_reaction_
  bool walls_changed_ = true;        // the candidates must be found again

  double time_ = 0.0;
  std::uint64_t steps_ = 0;
  double max_overlap_ratio_ = 0.0;
  std::size_t contacts_ = 0;
};

}  // namespace bushel
