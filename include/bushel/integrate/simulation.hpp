#pragma once
// The time stepper: particles, geometry parts, contact laws and the neighbour list brought
// together. Simulation owns the data (src/integrate/world.hpp) and runs a step as a fixed
// sequence of stages (src/integrate/stages.hpp; ARCHITECTURE.md, "The time step"):
//   1. neighbours: rebuild the neighbour list and the sphere-part candidates if an element or
//      part may have moved half the skin (spatially sorting the particles every few builds)
//   2. contacts, in parallel over fixed chunks of elements: sphere-sphere pairs (as first
//      element) and sphere-part contacts, through the contact law in batches
//   3. gather onto bodies and parts in a fixed order (thread-count independent)
//   4. servos act on the forces of step 2
//   5. integrate (symplectic Euler or velocity Verlet; quaternion rigid rotation)
//   6. move the geometry parts (motion.hpp)
// Particles enter through add_body and leave through remove_bodies.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "bushel/contact/contact_model.hpp"
#include "bushel/contact/contact_table.hpp"
#include "bushel/contact/neighbor_list.hpp"
#include "bushel/geometry/part.hpp"
#include "bushel/integrate/thread_governor.hpp"
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
  std::string rolling = "cdt";  ///< rolling model: cdt, epsd, liggghts_cdt, none (contact_model.hpp)
  /// Verlet skin [m]; 0 = adaptive, from 0.11 to 0.35 of the largest element diameter, as
  /// the particles' motion asks (Simulation::rebuild)
  double skin = 0.0;
  int sort_every = 20;    ///< spatial sort every N neighbour-list builds; 0 = never
  ContactTable contacts;  ///< restitution, friction, rolling friction per pair
  /// Largest share of a contact's relative tangential velocity that its damping may take in
  /// one step [-], gamma_t dt / m_t (contact_batch.hpp); infinity: the model's damping always.
  double tangential_damping_limit = 0.5;
  /// Threads of the parallel loops. The default leaves OpenMP's setting as the caller made it;
  /// adaptive measures which team size runs fastest (thread_governor.hpp). Results are the
  /// same bits at any thread count.
  ThreadPolicy threads;
};

namespace engine {
struct World;
}

class Simulation {
 public:
  explicit Simulation(SimulationSettings settings);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  /// The particles, to read and to set their state; add and remove them through add_type,
  /// add_body and remove_bodies.
  ParticleSystem& particles();
  const ParticleSystem& particles() const;
  /// Registers a particle type (its contact species) and returns its index; validates the
  /// material. Its coefficients with every other species are made before the next step.
  std::uint32_t add_type(ParticleType type);
  /// Adds a body of `type` at `state` and returns its stable id. It joins the contacts at the
  /// next step (a neighbour-list build); the last forces no longer stand for the state.
  std::uint32_t add_body(std::uint32_t type, const BodyState& state);
  /// Adds a geometry part; returns its index. Throws InputError (key "parts.<name>...") for
  /// a bad shape, material or motion, or a plane that is told to rotate.
  std::size_t add_part(Part part);
  const Part& part(std::size_t i) const;
  std::size_t parts() const;
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
  /// histories, time, the last step's force sums), for a checkpoint, as the sections
  /// engine.parts, engine.particles, engine.neighbors, engine.contacts and engine.diagnostics
  /// (each with its version). `load_state` into a simulation built with the same settings,
  /// types and parts continues bit for bit as the saved one would have; without
  /// engine.diagnostics it continues from zero force sums.
  void save_state(io::BinaryWriter& out) const;
  void load_state(const io::SectionTable& in);
  /// The names of the sections that save_state writes.
  static constexpr std::array<std::string_view, 5> state_sections{
      "engine.parts", "engine.particles", "engine.neighbors", "engine.contacts", "engine.diagnostics"};
  /// The checkpoint format that a run writes and reads (scenario_run.cpp): 4, named and
  /// versioned sections with checksums. A checkpoint of another format is refused.
  static constexpr int checkpoint_format = 4;

  /// Advances `n` steps.
  void step(std::uint64_t n = 1);

  double time() const;  ///< [s]
  std::uint64_t steps() const;
  const SimulationSettings& settings() const;
  /// The threads that the steps use now, and why (settings().threads).
  ThreadStatus threads() const;
  /// Sets the time step from the next step on [s]. Nothing else depends on it: the
  /// integrators take it per step, and the tangential and rolling springs grow by the
  /// displacement of each step, so a stage may run with its own step (scenario stages).
  void set_time_step(double dt);
  /// Largest overlap over the radius of the smaller sphere in the last step [-].
  double max_overlap_ratio() const;
  /// Largest max_overlap_ratio() of any step since the last reset [-]: a diagnostic, not part
  /// of the saved state.
  double peak_overlap_ratio() const;
  void reset_peak_overlap_ratio();
  /// The unbalanced force ratio of the last step [-]: the mean net force on a particle over
  /// the mean force of a contact (sphere-sphere, and sphere-part per sphere and part), as
  /// Yade defines it. It falls towards 0 as a packing comes to static equilibrium (about 1e-4
  /// is quasi-static, docs/wheat.md); 1 when nothing touches while a force acts, 0 with no particles.
  double unbalanced_force_ratio() const;
  /// Body b's total force of the last step, gravity included [N] (zero before the first step
  /// and for a body added since).
  const Vec3& body_force(std::size_t b) const;
  /// Its torque about the centre of mass, world frame [N m].
  const Vec3& body_torque(std::size_t b) const;
  /// Number of sphere-sphere contacts (overlap > 0) in the last step.
  std::size_t contacts() const;
  const NeighborList& neighbors() const;

 private:
  /// Readies the World for steps after changes from outside: the coefficient table for the
  /// species that exist, the neighbour list's configuration (once), the per-element arrays for
  /// the elements that exist, the elements placed; their displacements are measured afresh.
  void prepare_steps();
  /// Forces of the current state: stages 1 to 4.
  void compute_forces();

  std::unique_ptr<engine::World> w_;
};

}  // namespace bushel
