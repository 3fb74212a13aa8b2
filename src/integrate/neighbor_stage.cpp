// The neighbour stage: when to rebuild, the adaptive skin, the spatial sort, the sphere-part
// candidates and the chunks of the contact stage.

#include <algorithm>
#include <cmath>
#include <numeric>

#include "bushel/core/parallel.hpp"
#include "bushel/geometry/part_contact.hpp"
#include "stages.hpp"

namespace bushel::engine {
namespace {

// The adaptive skin: it widens when a build comes fewer than this many steps after the last,
// narrows when more, by this factor a build, between SkinControl::least and most.
constexpr std::uint64_t skin_widen_below_steps = 40;
constexpr std::uint64_t skin_narrow_above_steps = 160;
constexpr double skin_factor = 1.25;

// The adaptive skin trades the list's length (every pair in it is tested every step) against
// how often it is rebuilt (a build costs a few steps). Where the fastest element crossed half
// the skin in fewer than 40 steps (a stream falling from a funnel) the skin grows, up to
// 0.35 d; where it took more than 160 it shrinks, down to 0.11 d (a settled bed). It depends
// only on step counts, so every thread count follows the same skins.
void adapt_skin(NeighborList& neighbors, const SkinControl& skin, std::uint64_t steps) {
  if (!(skin.most > skin.least)) return;
  const std::uint64_t interval = steps - skin.last_build_step;
  if (interval < skin_widen_below_steps) neighbors.set_skin(std::min(skin.most, skin_factor * neighbors.skin()));
  if (interval > skin_narrow_above_steps) neighbors.set_skin(std::max(skin.least, neighbors.skin() / skin_factor));
}

// Bodies in the order of the cells of a grid (z-major, a cube of 1024 cells a side), so that
// neighbours in space become neighbours in memory; ties by stable id.
void spatial_sort(ParticleSystem& ps, double skin) {
  const std::size_t n = ps.bodies();
  if (n < 2) return;
  Vec3 lo{INFINITY, INFINITY, INFINITY};
  for (const auto& p : ps.position) lo = min(lo, p);
  double r_max = 0.0;
  for (const double r : ps.radius) r_max = std::max(r_max, r);
  const double cell = 2.0 * r_max + skin;
  std::vector<std::uint64_t> key(n);
  for (std::size_t b = 0; b < n; ++b) {
    const Vec3 c = (ps.position[b] - lo) / cell;
    auto q = [](double v) { return std::min<std::uint64_t>(1023, static_cast<std::uint64_t>(std::max(0.0, v))); };
    key[b] = (q(c.z) << 40) | (q(c.y) << 20) | q(c.x);
  }
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(),
            [&](auto a, auto b) { return key[a] != key[b] ? key[a] < key[b] : ps.body_id[a] < ps.body_id[b]; });
  ps.permute(order);  // part-contact histories follow the spheres' ids (find_part_candidates)
}

// The faces of part `w` within `reach` of the point p (in the part frame), appended to the
// candidates' face lists with their distances; returns whether there is any.
bool add_near_faces(const PartGeometry& pg, const Vec3& p, double reach, std::vector<std::uint32_t>& near,
                    PartCandidates& pc) {
  if (p.x < pg.lo.x - reach || p.y < pg.lo.y - reach || p.z < pg.lo.z - reach || p.x > pg.hi.x + reach ||
      p.y > pg.hi.y + reach || p.z > pg.hi.z + reach) {
    return false;
  }
  near.clear();
  if (pg.use_grid) {
    pg.grid.query(p, reach, near);
  } else {
    for (std::size_t f = 0; f < pg.faces.size(); ++f) near.push_back(static_cast<std::uint32_t>(f));
  }
  const std::size_t first_face = pc.faces.size();
  for (const std::uint32_t f : near) {
    const double d = nearest(pg.faces[f], p).distance;
    if (d < reach) pc.faces.push_back(f), pc.face_distance.push_back(d);
  }
  return pc.faces.size() > first_face;
}

// The candidates of the last build, for carrying their histories over by (sphere id, part).
struct OldCandidates {
  std::vector<std::uint32_t> first;  // [sphere id]: its first candidate, or UINT32_MAX
  std::vector<std::uint32_t> part, id;
  std::vector<double> history;
  OldCandidates(PartCandidates& pc, std::span<const std::uint32_t> sphere_ids)
      : first(sphere_ids.empty() ? 0 : *std::max_element(sphere_ids.begin(), sphere_ids.end()) + 1, UINT32_MAX),
        part(std::move(pc.part)),
        id(std::move(pc.sphere_id)),
        history(std::move(pc.history)) {
    for (std::size_t c = id.size(); c-- > 0;) {
      if (id[c] < first.size()) first[id[c]] = static_cast<std::uint32_t>(c);
    }
  }
  // Copies the history of (id, w), if it had one, to `to`.
  void carry(std::uint32_t sphere_id, std::uint32_t w, std::size_t slots, double* to) const {
    for (std::size_t c = sphere_id < first.size() ? first[sphere_id] : UINT32_MAX; c < id.size() && id[c] == sphere_id;
         ++c) {
      if (part[c] == w) std::copy_n(history.data() + c * slots, slots, to);
    }
  }
};

// The sphere-part candidates: no element moves more than half the skin between builds, and a
// build is due when a part has moved half the skin (move_parts), so a sphere further than the
// skin from a face cannot reach it before the next build.
void find_part_candidates(const ParticleSystem& ps, std::span<const Part> parts, std::span<PartGeometry> geometry,
                          const NeighborList& neighbors, PartCandidates& pc, std::vector<double>& element_moved2) {
  const std::size_t n_s = ps.spheres();
  const std::size_t slots = max_part_touches * (3 + static_cast<std::size_t>(neighbors.history_size()));
  const OldCandidates old(pc, ps.sphere_id);
  pc.start.assign(n_s + 1, 0);
  pc.part.clear();
  pc.sphere.clear();
  pc.sphere_id.clear();
  pc.face_start.assign(1, 0);
  pc.faces.clear();
  pc.face_distance.clear();
  element_moved2.assign(n_s, 0.0);
  pc.history.clear();
  std::vector<std::uint32_t> near;
  for (std::size_t s = 0; s < n_s; ++s) {
    const double reach = ps.radius[s] + neighbors.skin();
    for (std::size_t w = 0; w < parts.size(); ++w) {
      if (!parts[w].enabled) continue;
      const Vec3 p = transpose_times(geometry[w].rotation, ps.sphere_position[s] - parts[w].pose.position);
      if (!add_near_faces(geometry[w], p, reach, near, pc)) continue;
      pc.face_start.push_back(static_cast<std::uint32_t>(pc.faces.size()));
      pc.part.push_back(static_cast<std::uint32_t>(w));
      pc.sphere.push_back(static_cast<std::uint32_t>(s));
      pc.sphere_id.push_back(ps.sphere_id[s]);
      const std::size_t at = pc.history.size();
      pc.history.resize(at + slots, 0.0);
      old.carry(ps.sphere_id[s], static_cast<std::uint32_t>(w), slots, pc.history.data() + at);
    }
    pc.start[s + 1] = static_cast<std::uint32_t>(pc.part.size());
  }
  pc.reaction.assign(2 * pc.part.size(), Vec3{});
  pc.touches.assign(pc.part.size(), 0);
  for (PartGeometry& pg : geometry) pg.moved = 0.0;
  pc.stale = false;
}

// Runs of whole elements with about 256 pairs and part candidates each (with pair batches of
// 64, 3% faster than runs of 128; 512 was no faster): a fixed split (the thread count plays no
// part), and each element's own sums stay in one chunk.
void split_into_chunks(std::size_t n_s, const NeighborList& neighbors, const PartCandidates& pc,
                       std::vector<std::uint32_t>& chunk_start) {
  constexpr std::size_t chunk_load = 256;
  chunk_start.assign(1, 0);
  std::size_t load = 0;
  for (std::size_t s = 0; s < n_s; ++s) {
    load += neighbors.begin_of(s + 1) - neighbors.begin_of(s) + pc.start[s + 1] - pc.start[s];
    if (load >= chunk_load || s + 1 == n_s) {
      chunk_start.push_back(static_cast<std::uint32_t>(s + 1));
      load = 0;
    }
  }
}

// The largest squared displacement of an element since the last build [m2], each element's
// recorded in moved2 (for the part-face bound): after changes from outside, which the drift
// did not measure. An element added since the build has an infinite displacement.
double measure_displacements(const ParticleSystem& ps, const NeighborList& neighbors, std::vector<double>& moved2) {
  const auto& x = ps.sphere_position;
  const auto n = static_cast<std::ptrdiff_t>(x.size());
  double worst = 0.0;
#pragma omp parallel for schedule(static) reduction(max : worst) if (n > parallel_threshold)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const auto e = static_cast<std::size_t>(i);
    moved2[e] = neighbors.displacement2(e, x[e]);
    worst = std::max(worst, moved2[e]);
  }
  return worst;
}

}  // namespace

void rebuild_neighbors(World& w, bool adapt) {
  if (adapt) adapt_skin(w.neighbors, w.skin, w.steps);
  w.skin.last_build_step = w.steps;
  const int sort_every = w.settings.sort_every;
  if (sort_every > 0 && w.neighbors.builds() % static_cast<std::size_t>(sort_every) == 0) {
    spatial_sort(w.particles, w.neighbors.skin());
  }
  const auto& ps = w.particles;
  w.neighbors.build(ps.sphere_position, ps.radius, ps.owner, ps.sphere_id);
  find_part_candidates(ps, w.parts, w.geometry, w.neighbors, w.candidates, w.element_moved2);
  split_into_chunks(ps.spheres(), w.neighbors, w.candidates, w.sums.chunk_start);
}

void update_neighbors(World& w) {
  bool due = w.displacements == Displacements::past_skin, moved = due;
  if (w.displacements == Displacements::unknown) {
    const double worst = measure_displacements(w.particles, w.neighbors, w.element_moved2);
    due = w.neighbors.needs_rebuild(worst);
    // (not motion: the first build, or elements added since the last)
    moved = due && std::isfinite(worst) && w.neighbors.builds() > 0;
  }
  // A skin wider than the least is narrowed once 160 steps pass without a build, rather than
  // at the next build that motion causes, which is rare once the particles rest: a bed that
  // settles after a flow soon runs at the narrowest skin again.
  const bool narrow = w.neighbors.skin() > w.skin.least && w.steps - w.skin.last_build_step > skin_narrow_above_steps;
  if (w.candidates.stale || due || narrow) rebuild_neighbors(w, moved || narrow);
}

}  // namespace bushel::engine
