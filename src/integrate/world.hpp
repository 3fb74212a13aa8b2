#pragma once
// The simulation's data, internal to src/integrate: plain structs that the stages of a step
// (stages.hpp) read and write. Simulation (simulation.hpp) owns one World and runs the stages
// over it in a fixed order; nothing here is visible to the rest of the program.
//
// Index spaces: b a body, s a sphere element, p a pair of the neighbour list, c a part
// candidate (a sphere near a part), w a part, k a chunk (a run of whole elements, about 256
// pairs and candidates, the unit of work of the contact stage).

#include <cstdint>
#include <vector>

#include "bushel/contact/contact_model.hpp"
#include "bushel/contact/neighbor_list.hpp"
#include "bushel/contact/pair_coefficients.hpp"
#include "bushel/core/mat3.hpp"
#include "bushel/geometry/face_grid.hpp"
#include "bushel/geometry/part.hpp"
#include "bushel/integrate/simulation.hpp"
#include "bushel/integrate/thread_shares.hpp"
#include "bushel/particles/particle_system.hpp"
#include "team.hpp"

namespace bushel::engine {

/// A part's faces and broad phase in its own frame, and where the frame is now.
struct PartGeometry {
  std::vector<Face> faces;
  FaceGrid grid;  ///< used when the part has many faces (a mesh)
  bool use_grid = false;
  Vec3 lo, hi;         ///< bounds of the faces in the part frame [m]
  double reach = 0.0;  ///< largest distance of a face point from the part origin [m] (inf: a plane)
  Mat3 rotation;       ///< part frame -> world, now
  double moved = 0.0;  ///< bound on the displacement of any point since the last build [m]
};

/// An element's sums of forces, kept together: a pair's reaction goes to its second element,
/// a scattered one, whose sums then take one or two cache lines instead of three.
struct ElementSums {
  Vec3 force;        ///< [N]
  Vec3 torque;       ///< about its body's centre of mass [N m]
  double cdt = 0.0;  ///< CDT rolling resistance [N m]
};

/// Where the contact stage leaves its forces: per element the sum of its shares as second
/// element (where one thread computes all of an element's pairs as second; else one slot per
/// such pair, which the gather sums), and each body's totals in its first element's entry
/// (body_force in stages.hpp). An element's own sums (over its pairs as first element and its
/// parts) live only in the chunk's scratch: a body whose elements lie in one thread's chunks
/// and take all their shares as second from that thread gets its totals at the end of its
/// last element's chunk; the others' own sums are kept (deferred) for the gather.
struct ContactSums {
  // slots: the reaction on a second element that is not summed directly, one per pair it is
  // second of (scratch of one step: written for the touching pairs, read for those alone)
  std::vector<Vec3> pair_force;           ///< force on the first element (the second gets minus this) [N]
  std::vector<Vec3> pair_torque_j;        ///< torque on the second element's body [N m]
  std::vector<double> pair_cdt_j;         ///< CDT magnitude on the second element's body [N m]
  std::vector<std::uint32_t> slots_of;    ///< [s]: the element's slots are [slots_of[s], slots_of[s + 1]),
                                          ///< one per pair it is second of (none where second_direct)
  std::vector<std::uint32_t> slot_pair;   ///< [slot]: its pair; an element's slots in pair order
  std::vector<std::uint8_t> pair_active;  ///< [p]: 1 while the pair touches (or may: a fresh list)
  std::size_t active_build = 0;           ///< neighbour-list build the flags belong to
  // per element: the sum of its shares as second element, in pair order, kept by the contact
  // stage where second_direct (from zero); after the step, a body's first element holds the
  // body's totals and the other elements' entries are zero (put_totals in stages.hpp)
  std::vector<ElementSums> element;
  std::vector<std::uint8_t> second_direct;
  // the elements whose bodies are not finished in their chunk, ascending, their own sums (for
  // the gather), and per chunk k the first of them at or after chunk_start[k]
  std::vector<std::uint32_t> deferred;
  std::vector<ElementSums> deferred_own;
  std::vector<std::uint32_t> chunk_deferred;
  std::size_t direct_build = 0;            ///< neighbour-list build that second_direct and the slots are for
  int direct_team = 0;                     ///< and the team size (0: to be found again)
  std::vector<std::uint32_t> chunk_start;  ///< elements split into chunks: [chunk_start[k], chunk_start[k + 1])
  ThreadShares shares;                     ///< which chunks each thread takes (not part of the state)
};

/// Sphere-part candidates: the spheres within the skin of a part's faces at the last build,
/// grouped by sphere (CSR), each with its nearby faces and up to max_part_touches history
/// slots of [normal (3), contact-law history] keyed by the contact's normal (one slot where a
/// single face is near).
struct PartCandidates {
  std::vector<std::uint32_t> start;              ///< [s]: the sphere's candidates are [start[s], start[s + 1])
  std::vector<std::uint32_t> part;               ///< [c]: the part
  std::vector<std::uint32_t> sphere;             ///< [c]: the sphere element
  std::vector<std::uint32_t> sphere_id;          ///< [c]: its stable id (histories follow it across builds)
  std::vector<std::uint32_t> face_start, faces;  ///< [c]: its faces within the skin (CSR)
  std::vector<double> face_distance;             ///< centre to face at the build [m]
  /// [c]: its slots are [history_start[c], history_start[c + 1]); {0} before the first build,
  /// so that a checkpoint of a run stopped before its first step holds a valid empty list
  std::vector<std::uint32_t> history_start{0};
  std::vector<double> history;                   ///< [slot][3 + history size]
  std::vector<Vec3> reaction;         ///< [2 c]: force on the part [N], its torque about the part origin [N m]
  std::vector<std::uint8_t> touches;  ///< [c]: contacts in the last step
  std::vector<Vec3> partial;          ///< per-block sums of reaction (sum_part_reactions)
  bool stale = true;                  ///< parts changed or moved half the skin: find them again
};

/// Whether a part candidate's history slot (PartCandidates::history) holds a contact: a slot
/// in use keeps the contact's unit normal, a free one is all zeros.
inline bool history_slot_in_use(const double* slot) { return norm2(Vec3{slot[0], slot[1], slot[2]}) != 0.0; }

/// The adaptive skin's range and clock (neighbor_stage.cpp).
struct SkinControl {
  double least = 0.0, most = 0.0;     ///< the skin's range [m]: equal when it is fixed
  std::uint64_t last_build_step = 0;  ///< steps at the last neighbour-list build
};

/// What a step measured, for the run's checks and the unbalanced force ratio.
struct StepDiagnostics {
  double max_overlap_ratio = 0.0;       ///< largest overlap over the smaller radius, last step [-]
  double peak_overlap_ratio = 0.0;      ///< largest of those since the last reset [-]
  std::vector<double> chunk_force_sum;  ///< per chunk: its pairs' force magnitudes [N]
  double pair_force_sum = 0.0;          ///< force magnitudes of the sphere-sphere contacts [N]
  double part_force_sum = 0.0;          ///< force magnitudes of the sphere-part contacts [N]
  std::size_t part_contacts = 0;        ///< spheres touching a part, per part
  std::size_t contacts = 0;             ///< sphere-sphere contacts
};

/// Whether the elements' displacements since the last build are known to be within half the
/// skin: the drift measures them; anything done from outside (insertion, a restart) makes
/// them unknown, and the neighbour stage measures them itself. Stored as an int (-1, 0, 1).
enum class Displacements : int { unknown = -1, within_skin = 0, past_skin = 1 };

/// The coefficients and the neighbour list's configuration follow the particle types and
/// parts that exist: these record what they were made for (Simulation::prepare_steps).
struct Configuration {
  std::size_t types = 0, parts = 0;  ///< counts the coefficient table was made for
  bool neighbors = false;            ///< the neighbour list has its skin and history size
};

struct World {
  SimulationSettings settings;
  RollingModel rolling;
  ParticleSystem particles;
  std::vector<Part> parts;
  std::vector<PartGeometry> geometry;  ///< [w]
  NeighborList neighbors{1.0, 3};
  PairCoefficientTable coefficients;  ///< over species: particle types, then parts
  ContactSums sums;
  PartCandidates candidates;
  SkinControl skin;
  StepDiagnostics diagnostics;
  Configuration configured;
  Displacements displacements = Displacements::unknown;
  /// The bodies' forces belong to the current state (velocity Verlet's first half kick);
  /// false after add_body, add_part and remove_bodies until the next forces.
  bool forces_valid = false;
  double time = 0.0;  ///< [s]
  std::uint64_t steps = 0;
  Team team{ThreadPolicy{}};  ///< the thread count of the steps (not part of the state)
};

}  // namespace bushel::engine
