// Simulation::save_state and load_state: the whole dynamic state, for a checkpoint, as the
// engine's named sections (binary_archive.hpp). A change to a section's layout is a new
// version of that section.

#include <fmt/format.h>

#include <type_traits>

#include "bushel/core/input_error.hpp"
#include "bushel/geometry/part_contact.hpp"
#include "bushel/integrate/simulation.hpp"
#include "bushel/io/binary_archive.hpp"
#include "stages.hpp"

namespace bushel {
namespace {

// Calls f on element sums as a checkpoint keeps them: three columns (force, torque, CDT), read
// back into `sums` when it is not const.
template <class S, class F>
void each_sums_column(S& sums, F&& f) {
  std::vector<Vec3> force(sums.size()), torque(sums.size());
  std::vector<double> cdt(sums.size());
  if constexpr (std::is_const_v<S>) {
    for (std::size_t s = 0; s < sums.size(); ++s)
      force[s] = sums[s].force, torque[s] = sums[s].torque, cdt[s] = sums[s].cdt;
  }
  f(force), f(torque), f(cdt);
  if constexpr (!std::is_const_v<S>) {
    if (torque.size() != force.size() || cdt.size() != force.size()) {
      throw InputError("the checkpoint's contact sums do not fit together (a damaged file?)");
    }
    sums.resize(force.size());
    for (std::size_t s = 0; s < sums.size(); ++s) sums[s] = {.force = force[s], .torque = torque[s], .cdt = cdt[s]};
  }
}

// Calls f on each member that save_state writes after the neighbour list, in file order: one
// list for writing and reading (W is World or const World). `moved2`: where a version 1 or 2
// section held each element's displacement since the build (found again from the neighbour
// list now), to be read and dropped; null from version 3. `slot_index`: the part candidates'
// history slots are indexed (version 4; before, each candidate had max_part_touches).
// `second_sums`: where a section before version 5 held the elements' own sums (into
// ContactSums::element, whose first elements' entries hold the bodies' totals as the own sums
// did) and then their sums as second element (zero between steps), to be read and dropped.
template <class W, class F>
void each_saved_member(W& w, F&& f, std::vector<double>* moved2 = nullptr, bool slot_index = true,
                       std::vector<engine::ElementSums>* second_sums = nullptr) {
  static_assert(std::is_same_v<std::size_t, std::uint64_t>, "counts are stored as 64-bit");
  auto& s = w.sums;
  auto& c = w.candidates;
  f(s.pair_active);
  each_sums_column(s.element, f);
  if (second_sums) each_sums_column(*second_sums, f);
  f(s.second_direct);
  f(s.chunk_start);
  f(c.start);
  f(c.part);
  f(c.sphere);
  f(c.sphere_id);
  f(c.face_start);
  f(c.faces);
  f(c.face_distance);
  if (moved2) f(*moved2);
  if (slot_index) f(c.history_start);
  f(c.history);
  f(c.reaction);
  f(c.touches);
  f(c.partial);
  f(w.forces_valid);
  f(w.displacements);
  f(c.stale);
  f(s.direct_team);
  f(w.time);
  f(w.steps);
  f(w.diagnostics.max_overlap_ratio);
  f(s.active_build);
  f(s.direct_build);
  f(w.diagnostics.contacts);
}

// Calls f on each saved field of a part and its geometry, in file order (P is Part or const
// Part): its pose, motion, servo and last forces.
template <class P, class G, class F>
void each_part_field(P& p, G& g, F&& f) {
  f(p.pose);
  f(p.enabled);
  f(p.motion.segments);
  f(p.motion.has_servo);
  f(p.motion.servo);
  f(p.force);
  f(p.torque);
  f(p.twist);
  f(p.servo);
  f(p.touches);
  f(g.moved);
}

void save_parts(io::BinaryWriter& out, const engine::World& w) {
  out.put(static_cast<std::uint64_t>(w.parts.size()));
  for (std::size_t i = 0; i < w.parts.size(); ++i) {
    each_part_field(w.parts[i], w.geometry[i], [&](const auto& m) { out.put(m); });
  }
}

void load_parts(io::BinaryReader& in, engine::World& w) {
  if (in.get<std::uint64_t>() != w.parts.size()) {
    throw InputError("the checkpoint has another number of geometry parts than the scenario");
  }
  for (std::size_t i = 0; i < w.parts.size(); ++i) {
    each_part_field(w.parts[i], w.geometry[i], [&](auto& m) { in.get(m); });
    w.geometry[i].rotation = to_matrix(w.parts[i].pose.orientation);
  }
}

// Reads a saved member; the displacement state is an int that must be one of its values.
template <class T>
void get_member(io::BinaryReader& in, T& m) {
  if constexpr (std::is_same_v<T, engine::Displacements>) {
    const int v = in.get<int>();
    if (v < -1 || v > 1) in.damaged("a displacement state that is neither -1, 0 nor 1");
    m = static_cast<engine::Displacements>(v);
  } else {
    in.get(m);
  }
}

// The part candidates' history slots: indexed from version 4, before max_part_touches each.
void check_history_slots(engine::World& w, bool indexed) {
  engine::PartCandidates& c = w.candidates;
  const std::size_t n_c = c.part.size(), slot_size = 3 + static_cast<std::size_t>(w.neighbors.history_size());
  constexpr auto most = static_cast<std::size_t>(max_part_touches);
  if (!indexed) {
    c.history_start.resize(n_c + 1);
    for (std::size_t k = 0; k <= n_c; ++k) c.history_start[k] = static_cast<std::uint32_t>(k * most);
  }
  const auto& start = c.history_start;
  bool fits = start.size() == n_c + 1 && start.front() == 0 && c.history.size() == start.back() * slot_size;
  for (std::size_t k = 0; fits && k < n_c; ++k) {
    fits = start[k] <= start[k + 1] && start[k + 1] - start[k] <= most;
  }
  if (!fits) throw InputError("the checkpoint's part contact histories do not fit together (a damaged file?)");
}

// The bodies' last forces from a particles section of version 1 or 2 into their first
// elements' entries, where the contact stage and the gather leave them (body_force).
void put_saved_forces(engine::World& w, const ParticleSystem::SavedForces& saved) {
  const ParticleSystem& ps = w.particles;
  if (saved.force.empty()) return;
  // (sums for fewer elements: bodies added since the last step, whose forces are not valid yet)
  if (w.sums.element.size() > ps.spheres()) {
    throw InputError("the checkpoint's contact sums do not match its particles (a damaged file?)");
  }
  w.sums.element.resize(ps.spheres());
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    const std::uint32_t s0 = ps.first_sphere[b];
    w.sums.element[s0] = {.force = saved.force[b], .torque = saved.torque[b], .cdt = saved.rolling_resistance[b]};
  }
}

// Between steps only a body's first element's entry of the sums is not zero (put_totals);
// before version 5 the others held the elements' own sums.
void clear_other_elements(engine::World& w) {
  const ParticleSystem& ps = w.particles;
  std::vector<engine::ElementSums>& element = w.sums.element;
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    const std::size_t s0 = ps.first_sphere[b], s1 = std::min<std::size_t>(s0 + ps.sphere_count[b], element.size());
    if (s0 < s1)
      std::fill(element.begin() + static_cast<std::ptrdiff_t>(s0) + 1,
                element.begin() + static_cast<std::ptrdiff_t>(s1), engine::ElementSums{});
  }
}

}  // namespace

// The engine's sections of a checkpoint and their versions: each is written and read here by
// the part of the World it holds. Earlier versions still load:
// - engine.neighbors: version 3 keeps the elements' ids at the build instead of each pair's
//   stable identity; version 4 leaves out the index of the pairs by second element, which the
//   contact stage keeps where threads share an element (loading versions 1 to 3 skips it).
// - engine.contacts: version 1 held the second elements' slots too (one per pair), which are
//   the scratch of a step: version 2 leaves them out. Version 3 holds the bodies' last forces
//   (in the first elements' own sums) and no longer the elements' displacements since the
//   build. Version 4 indexes the part candidates' history slots, which were max_part_touches
//   each before. Version 5 keeps one sums array per element (the bodies' totals in their first
//   elements' entries) instead of the elements' own sums and their sums as second element.
// - engine.particles: version 1 held each body's principal moments and each element's centre,
//   which version 2 leaves to the particle types (version 1 still loads, if they agree);
//   version 3 leaves each body's mass to its type and its last forces to the contact sums.
constexpr std::uint32_t parts_version = 1, particles_version = 3, neighbors_version = 4, contacts_version = 5,
                        diagnostics_version = 1;

void Simulation::save_state(io::BinaryWriter& out) const {
  const engine::World& w = *w_;
  io::BinaryWriter parts, particles, neighbors, contacts, diagnostics;
  save_parts(parts, w);
  w.particles.save(particles);
  w.neighbors.save(neighbors);
  each_saved_member(w, [&](const auto& m) { contacts.put(m); });
  diagnostics.put(w.diagnostics.pair_force_sum);
  diagnostics.put(w.diagnostics.part_force_sum);
  diagnostics.put(static_cast<std::uint64_t>(w.diagnostics.part_contacts));
  diagnostics.put(w.skin.last_build_step);
  out.put_section("engine.parts", parts_version, parts);
  out.put_section("engine.particles", particles_version, particles);
  out.put_section("engine.neighbors", neighbors_version, neighbors);
  out.put_section("engine.contacts", contacts_version, contacts);
  out.put_section("engine.diagnostics", diagnostics_version, diagnostics);
}

void Simulation::load_state(const io::SectionTable& in) {
  engine::World& w = *w_;
  in.read("engine.parts", parts_version, true, [&](io::BinaryReader& b) { load_parts(b, w); });
  ParticleSystem::SavedForces saved;
  {
    io::SectionTable::Section s = in.get("engine.particles", particles_version);
    saved = w.particles.load(s.body, s.version);
    io::SectionTable::expect_end(s.body, "engine.particles");
  }
  // The derived tables (pair coefficients) and the neighbour list's configuration, then the
  // saved list and every per-pair and per-element array over them.
  const std::vector<Vec3> placed = w.particles.sphere_position;
  prepare_steps();
  w.particles.sphere_position = placed;
  {
    io::SectionTable::Section s = in.get("engine.neighbors", neighbors_version);
    w.neighbors.load(s.body, s.version);
    io::SectionTable::expect_end(s.body, "engine.neighbors");
    if (const int h = history_size(w.rolling); w.neighbors.history_size() != h) {
      throw InputError(
          fmt::format("the checkpoint's contacts keep {} history values each, the scenario's rolling model {} (another "
                      "rolling model?)",
                      w.neighbors.history_size(), h));
    }
  }
  {
    io::SectionTable::Section s = in.get("engine.contacts", contacts_version);
    if (s.version == 1) {
      std::vector<Vec3> force, torque;
      std::vector<double> cdt;
      s.body.get(force), s.body.get(torque), s.body.get(cdt);
    }
    std::vector<double> moved2;
    std::vector<engine::ElementSums> second_sums;
    each_saved_member(
        w, [&](auto& m) { get_member(s.body, m); }, s.version < 3 ? &moved2 : nullptr, s.version >= 4,
        s.version < 5 ? &second_sums : nullptr);
    io::SectionTable::expect_end(s.body, "engine.contacts");
    check_history_slots(w, s.version >= 4);
    put_saved_forces(w, saved);
    clear_other_elements(w);
    w.sums.direct_team = 0;  // (the slots are found again at the first step)
  }
  // Without its diagnostics a state still continues (the unbalanced force ratio is unknown
  // until the next step, the adaptive skin counts from the checkpoint's step).
  w.diagnostics.pair_force_sum = w.diagnostics.part_force_sum = 0.0;
  w.diagnostics.part_contacts = 0;
  w.skin.last_build_step = w.steps;
  in.read("engine.diagnostics", diagnostics_version, false, [&](io::BinaryReader& b) {
    b.get(w.diagnostics.pair_force_sum);
    b.get(w.diagnostics.part_force_sum);
    w.diagnostics.part_contacts = static_cast<std::size_t>(b.get<std::uint64_t>());
    b.get(w.skin.last_build_step);
  });
}

}  // namespace bushel
