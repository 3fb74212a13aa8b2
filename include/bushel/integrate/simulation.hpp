#pragma once
// The time stepper: particles, geometry parts, contact laws and the neighbour list brought together
// (ARCHITECTURE.md, "Time step"). One step:
//   1. rebuild the neighbour list if needed (spatially sorting the particles every few builds)
//   2. contacts, in parallel over fixed runs of elements (each about 128 pairs and part
//      candidates): every element sums its own pairs (as first element) and its nearby
//      geometry parts (part_contact.hpp: one contact per touch of a part's surface); the share
//      of each pair's second element goes to the pair's slot. The contact law runs over
//      batches of contacts at once (contact_batch.hpp).
//   3. gather onto bodies in a fixed order (thread-count independent): the elements' own
//      sums plus their shares as second element, summed in pair order (by the contact loop
//      where one thread has all of an element's pairs as second, else here from pair slots)
//   4. integrate (symplectic Euler or velocity Verlet; quaternion rigid rotation)
//   5. move the geometry parts (motion.hpp), servos acting on the forces of step 2

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "bushel/contact/contact_model.hpp"
#include "bushel/contact/contact_table.hpp"
#include "bushel/contact/neighbor_list.hpp"
#include "bushel/contact/pair_coefficients.hpp"
#include "bushel/core/mat3.hpp"
#include "bushel/geometry/face_grid.hpp"
#include "bushel/geometry/part.hpp"
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
  /// Verlet skin [m]; 0 = adaptive, from 0.11 to 0.35 of the largest element diameter, as
  /// the particles' motion asks (Simulation::rebuild)
  double skin = 0.0;
  int sort_every = 20;    ///< spatial sort every N neighbour-list builds; 0 = never
  ContactTable contacts;  ///< restitution, friction, rolling friction per pair
  /// Largest share of a contact's relative tangential velocity that its damping may take in
  /// one step [-], gamma_t dt / m_t (contact_batch.hpp); infinity: the model's damping always.
  double tangential_damping_limit = 0.5;
};

/// A part's faces and broad phase in its own frame, and where the frame is now (internal to
/// the simulation; public so that the contact loop can read it).
struct PartCache {
  std::vector<Face> faces;
  FaceGrid grid;  ///< used when the part has many faces (a mesh)
  bool use_grid = false;
  Vec3 lo, hi;         ///< bounds of the faces in the part frame [m]
  double reach = 0.0;  ///< largest distance of a face point from the part origin [m] (inf: a plane)
  Mat3 rotation;       ///< part frame -> world, now
  double moved = 0.0;  ///< bound on the displacement of any point since the last build [m]
};

class Simulation {
 public:
  explicit Simulation(SimulationSettings settings);

  ParticleSystem& particles() { return particles_; }
  const ParticleSystem& particles() const { return particles_; }
  /// Adds a geometry part; returns its index. Throws InputError (key "parts.<name>...") for
  /// a bad shape, material or motion, or a plane that is told to rotate.
  std::size_t add_part(Part part);
  const Part& part(std::size_t i) const { return parts_[i]; }
  std::size_t parts() const { return parts_.size(); }
  /// Index of the part called `name`; throws InputError listing the names if there is none.
  std::size_t part_index(const std::string& name) const;
  /// Replaces a part's motion from now on (validated as in add_part).
  void set_motion(std::size_t i, Motion motion);
  /// Takes a part out of the contacts (false) or puts it back (true) from the next step.
  void set_part_enabled(std::size_t i, bool enabled);
  /// Faces of a part in the world at its current pose, as triangles (for export).
  TriangleMesh part_surface(std::size_t i, int segments = 64, double plane_half_size = 0.1) const;

  /// Removes bodies (indices into particles(), any order, no repeats) with their elements.
  /// The others keep their contacts and contact history (keyed by stable ids); the next step
  /// rebuilds the neighbour list.
  void remove_bodies(std::span<const std::size_t> bodies);

  /// The whole dynamic state (particles, parts' poses, motions and servos, contact lists and
  /// histories, time), for a checkpoint. `load_state` into a simulation built with the same
  /// settings, types and parts continues bit for bit as the saved one would have.
  void save_state(io::BinaryWriter& out) const;
  /// The checkpoint format that a run writes and reads (scenario_run.cpp): 3, sections with
  /// checksums. A checkpoint of another format is refused.
  static constexpr int checkpoint_format = 3;
  void load_state(io::BinaryReader& in);
  /// The last step's contact force sums (of unbalanced_force_ratio), which save_state leaves
  /// out (a checkpoint stores them after it).
  void save_force_sums(io::BinaryWriter& out) const;
  void load_force_sums(io::BinaryReader& in);
  /// The step of the last neighbour-list build, which the adaptive skin measures from (the
  /// skin itself is in the list), stored after the force sums.
  void save_skin_clock(io::BinaryWriter& out) const;
  void load_skin_clock(io::BinaryReader& in);

  /// Advances `n` steps.
  void step(std::uint64_t n = 1);

  double time() const { return time_; }  ///< [s]
  std::uint64_t steps() const { return steps_; }
  const SimulationSettings& settings() const { return settings_; }
  /// Sets the time step from the next step on [s]. Nothing else depends on it: the
  /// integrators take it per step, and the tangential and rolling springs grow by the
  /// displacement of each step, so a stage may run with its own step (scenario stages).
  void set_time_step(double dt);
  /// Largest overlap over the radius of the smaller sphere in the last step [-].
  double max_overlap_ratio() const { return max_overlap_ratio_; }
  /// Largest max_overlap_ratio() of any step since the last reset [-]: a diagnostic, not part
  /// of the saved state.
  double peak_overlap_ratio() const { return peak_overlap_ratio_; }
  void reset_peak_overlap_ratio() { peak_overlap_ratio_ = 0.0; }
  /// The unbalanced force ratio of the last step [-]: the mean net force on a particle over
  /// the mean force of a contact (sphere-sphere, and sphere-part per sphere and part), as
  /// Yade defines it. It falls towards 0 as a packing comes to static equilibrium (about 1e-4
  /// is quasi-static, wheat.md); 1 when nothing touches while a force acts, 0 with no particles.
  double unbalanced_force_ratio() const;
  /// Number of sphere-sphere contacts (overlap > 0) in the last step.
  std::size_t contacts() const { return contacts_; }
  const NeighborList& neighbors() const { return neighbors_; }

 private:
  void prepare();
  /// Builds the lists; `adapt_skin` when the build is due to motion (or to narrow the skin),
  /// so that the adaptive skin may change first.
  void rebuild(bool adapt_skin = false);
  void find_part_candidates();
  void move_parts(double t, double dt);
  void update_servos();
  void split_into_chunks();
  void mark_direct_seconds(int team);
  void spatial_sort();
  template <class Rolling>
  void compute_forces(const Rolling&);
  void compute_forces();
  void sum_part_reactions();
  void kick(double dt);
  void drift(double dt);
  /// Calls f on each member that save_state writes after the neighbour list, in file order.
  template <class Self, class F>
  static void each_saved_member(Self& self, F&& f);

  SimulationSettings settings_;
  RollingModel rolling_;
  ParticleSystem particles_;
  std::vector<Part> parts_;
  std::vector<PartCache> part_cache_;
  NeighborList neighbors_;
  PairCoefficientTable coefficients_;
  std::size_t prepared_types_ = 0, prepared_parts_ = 0;
  bool forces_valid_ = false;
  std::size_t forces_parts_ = 0;  // part count the last forces were computed with
  int rebuild_due_ = -1;          // from the last drift: 1 yes, 0 no, -1 unknown (check every element)
  bool neighbors_configured_ = false;
  double skin_min_ = 0.0, skin_max_ = 0.0;  // the skin's range [m]: equal when it is fixed
  std::uint64_t last_build_step_ = 0;       // steps_ at the last neighbour-list build

  // per pair: the reaction on the second element from the last force computation, written
  // only for touching pairs whose second element is not summed directly (second_direct_)
  std::vector<Vec3> pair_force_;           // force on the first element (the second gets minus this) [N]
  std::vector<Vec3> pair_torque_j_;        // torque on the second element's body [N m]
  std::vector<double> pair_cdt_j_;         // CDT magnitude on the second element's body [N m]
  std::vector<std::uint8_t> pair_active_;  // 1 while the pair touches (or may: fresh list)
  std::size_t active_build_ = 0;           // neighbour-list build the flags belong to
  // per element: its own sums over its pairs (as first element) and its parts
  std::vector<Vec3> element_force_, element_torque_;
  std::vector<double> element_cdt_;
  // per element: the sum of its shares as second element, in pair order, kept by the contact
  // loop where one thread computes all of them (second_direct_), else summed from the pair
  // slots by the gather; zero between steps
  std::vector<Vec3> second_force_, second_torque_;
  std::vector<double> second_cdt_;
  std::vector<std::uint8_t> second_direct_;
  std::size_t direct_build_ = 0;  // neighbour-list build and team size second_direct_ is for
  int direct_team_ = 0;
  std::vector<std::uint32_t> chunk_start_;  // elements split into runs of about one batch of contacts
  // sphere-part candidates (spheres within the skin of a part's faces at the last build),
  // grouped by sphere (CSR), each with its nearby faces and max_part_touches history slots
  // of [normal (3), contact-law history] keyed by the contact's normal
  std::vector<std::uint32_t> part_start_, part_of_candidate_, sphere_of_candidate_, candidate_sphere_id_;
  std::vector<std::uint32_t> candidate_face_start_, candidate_faces_;
  std::vector<double> candidate_face_distance_;  // centre to face at the build [m]
  std::vector<double> element_moved2_;           // squared displacement of each element since the build [m2]
  std::vector<double> part_history_;
  std::vector<Vec3> part_reaction_;              // [2 c]: force on the part, its torque about the part origin
  std::vector<std::uint8_t> candidate_touches_;  // [c]: contacts in the last step
  std::vector<Vec3> part_partial_;               // per-chunk sums of part_reaction_
  bool parts_changed_ = true;                    // the candidates must be found again

  double time_ = 0.0;
  std::uint64_t steps_ = 0;
  double max_overlap_ratio_ = 0.0;
  double peak_overlap_ratio_ = 0.0;
  std::vector<double> chunk_force_sum_;  // per chunk of elements: its pairs' force magnitudes [N]
  double pair_force_sum_ = 0.0;          // force magnitudes of the sphere-sphere contacts [N]
  double part_force_sum_ = 0.0;          // force magnitudes of the sphere-part contacts [N]
  std::size_t part_contacts_ = 0;        // spheres touching a part, per part
  std::size_t contacts_ = 0;
};

}  // namespace bushel
