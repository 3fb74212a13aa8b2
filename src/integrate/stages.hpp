#pragma once
// The stages of a time step (internal to src/integrate), in the order Simulation::step runs
// them (ARCHITECTURE.md, "The time step"):
//
//   neighbours      update_neighbors     (neighbor_stage.cpp)
//   contacts        compute_contacts     (contact_stage.cpp: sphere-sphere, then sphere-part per chunk)
//   gather          sum_part_reactions, gather (gather_stage.cpp)
//   servos          update_servos        (part_stage.cpp)
//   integrate       kick, drift          (integrate_stage.cpp)
//   move parts      move_parts           (part_stage.cpp)
//
// Each stage takes the few structs of the World it reads and writes. Every sum whose order
// could depend on the thread count is taken in a fixed order (per chunk, per block, per body),
// so the results are the same bits for any thread count. Another backend (GPU, MPI domains)
// would implement the same stages over the same arrays.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "bushel/core/parallel.hpp"
#include "world.hpp"

namespace bushel::engine {

/// Whether a loop over the bodies runs in parallel: counted in elements, the work the bodies
/// bring (a 5-sphere clump places five elements and turns), not in bodies.
inline bool parallel_work(const ParticleSystem& ps) {
  return static_cast<std::ptrdiff_t>(ps.spheres()) > parallel_threshold;
}

// --- neighbours (neighbor_stage.cpp) -------------------------------------------------------
/// Rebuilds the neighbour list and the part candidates when an element or a part may have
/// moved half the skin since the last build, when the candidates are stale, or when a skin
/// wider than the least has gone 160 steps without a build.
void update_neighbors(World& w);
/// Rebuilds them now; `adapt_skin` when the build is due to motion (or to narrow the skin),
/// so that the adaptive skin may change first.
void rebuild_neighbors(World& w, bool adapt_skin);

// --- contacts (contact_stage.cpp) ----------------------------------------------------------
/// Every contact's force and torque into ContactSums and PartCandidates::reaction, with the
/// largest overlap and the force sums into StepDiagnostics.
void compute_contacts(World& w);

// --- gather (gather_stage.cpp) --------------------------------------------------------------
/// Each part's force, torque and touches from its candidates' reactions, summed in fixed
/// blocks; the sphere-part force sums into `d`.
void sum_part_reactions(PartCandidates& candidates, std::span<Part> parts, StepDiagnostics& d);
/// A body's totals (ContactSums::element) in a fixed order: its weight [N], then element by
/// element its own sums (`own(s)`) and its sums as second element (`second(s)`) over its
/// elements [s0, s0 + n). The contact stage (for the bodies it finishes) and the gather (for
/// the deferred ones) both take them here, so they are the same bits for any thread count.
template <class Own, class Second>
ElementSums body_totals(const Vec3& weight, std::uint32_t s0, std::uint32_t n, Own&& own, Second&& second) {
  Vec3 f = weight, t;
  double cdt = 0.0;
  for (std::uint32_t s = s0; s < s0 + n; ++s) {
    const ElementSums& o = own(s);
    f += o.force;
    t += o.torque;
    cdt += o.cdt;
    const ElementSums& as_second = second(s);  // (a temporary where second gives a value)
    f += as_second.force;
    t += as_second.torque;
    cdt += as_second.cdt;
  }
  return {.force = f, .torque = t, .cdt = cdt};
}
/// A body's totals into its first element's entry, and its other elements' entries (their
/// shares as second, now read) back to zero: between steps only the first elements' entries
/// are not zero, and only those need zeroing before the next contact stage.
inline void put_totals(std::span<ElementSums> element, std::uint32_t s0, std::uint32_t n, const ElementSums& totals) {
  element[s0] = totals;
  std::fill(element.begin() + s0 + 1, element.begin() + s0 + n, ElementSums{});
}
/// The totals of the bodies that the contact stage left to it (ContactSums::deferred), from
/// their elements' own sums and their shares as second element (summed from the pair slots
/// where the contact stage did not), into their first elements' entries (body_force).
void gather(const ParticleSystem& ps, ContactSums& sums, const Vec3& gravity);
/// Body b's total force of the last step [N], torque about its centre of mass [N m] and CDT
/// rolling resistance [N m], as the contact stage and the gather left them (until the next
/// contact stage). The steps read them directly; between steps, Simulation::body_force gives
/// zero for a body added since the last step (whose element has no sums yet).
inline const Vec3& body_force(const ParticleSystem& ps, const ContactSums& sums, std::size_t b) {
  return sums.element[ps.first_sphere[b]].force;
}
inline const Vec3& body_torque(const ParticleSystem& ps, const ContactSums& sums, std::size_t b) {
  return sums.element[ps.first_sphere[b]].torque;
}
inline double body_rolling_resistance(const ParticleSystem& ps, const ContactSums& sums, std::size_t b) {
  return sums.element[ps.first_sphere[b]].cdt;
}
/// Whether body b has sums (it existed at the last step's start).
inline bool has_sums(const ParticleSystem& ps, const ContactSums& sums, std::size_t b) {
  return ps.first_sphere[b] < sums.element.size();
}
/// The elements' sums (and with them the bodies' totals) reordered as the elements were
/// (ParticleSystem::permute's sphere order: new index -> old), so that the totals follow
/// their bodies.
void permute_body_sums(ContactSums& sums, std::span<const std::uint32_t> sphere_order);
/// The unbalanced force ratio of the last step [-] (Simulation::unbalanced_force_ratio).
double unbalanced_force_ratio(const ParticleSystem& ps, const ContactSums& sums, const StepDiagnostics& d);

// --- integrate (integrate_stage.cpp) --------------------------------------------------------
/// Velocities and angular momenta over dt [s] from the bodies' forces and torques (body_force);
/// the constant directional rolling torque is capped so that it can stop a spin but never
/// reverse it.
void kick(ParticleSystem& ps, const ContactSums& sums, double dt);
/// Positions and orientations over dt [s], the elements placed and their displacement since
/// the last build measured; returns whether a build is due.
Displacements drift(ParticleSystem& ps, const NeighborList& neighbors, double dt);

// --- parts (part_stage.cpp) -----------------------------------------------------------------
/// A part's faces, bounds and broad phase; throws InputError for a bad shape.
PartGeometry make_part_geometry(const Part& part);
/// Each moving part's pose and twist over [t, t + dt]; marks the candidates stale once a part
/// has moved half the skin since the last build.
void move_parts(std::span<Part> parts, std::span<PartGeometry> geometry, double skin, double t, double dt,
                PartCandidates& candidates);
/// Each servo's action from the force the particles put on its part in the last contacts.
void update_servos(std::span<Part> parts, double time);

}  // namespace bushel::engine
