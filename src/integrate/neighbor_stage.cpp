// The neighbour stage: when to rebuild, the adaptive skin, the spatial sort, the sphere-part
// candidates and the chunks of the contact stage.

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include "bushel/core/parallel.hpp"
#include "bushel/geometry/part_contact.hpp"
#include "stages.hpp"

namespace bushel::engine {
namespace {

// The adaptive skin trades the list's length (every pair in it is tested every step) against
// how often it is rebuilt. A build costs about build_cost_per_element pair tests for each
// element (the grid, the scan of the cells around it, the part candidates) and build_cost_per_pair for
// each pair it lists (flow-early of the full-size cup, large_5s: 0.37 us an element, 0.03 us
// a pair, where a step spends 5.2 ns a pair in the list; bench/results/adaptive-skin.md).
constexpr double build_cost_per_element = 72.0;  // [pair tests]
constexpr double build_cost_per_pair = 6.0;      // [pair tests]
// The most the skin changes at one build (the model is fitted to one interval), and the
// least change worth a build of its own when no element has moved.
constexpr double skin_step_most = 2.0;
constexpr double skin_narrow_least = 1.25;
// Steps without a build after which a wide skin is checked (then again at twice as many).
constexpr std::uint64_t skin_check_steps = 160;

// Margins per element (docs/engine.md): an element faster than wide_speed_least times the
// speed of the wide_quantile-th element gets a margin as many times half the skin as it is
// faster than that (at most wide_margin_most times), so that it takes as long to cross it as
// the others take to cross theirs: the few grains falling fast no longer set how often the
// whole list is rebuilt.
constexpr double wide_quantile = 0.98;
constexpr double wide_speed_least = 2.0;
constexpr double wide_margin_most = 4.0;

// The speed of each element at most [m/s]: its body's speed and its turning about the centre.
std::vector<double> element_speeds(const ParticleSystem& ps) {
  std::vector<double> speed(ps.spheres());
  for (std::size_t e = 0; e < speed.size(); ++e) {
    const std::uint32_t b = ps.owner[e];
    speed[e] = norm(ps.velocity[b]) + norm(ps.angular_velocity[b]) * norm(ps.sphere_position[e] - ps.position[b]);
    if (std::isnan(speed[e]))
      speed[e] = std::numeric_limits<double>::infinity();  // (a run gone wrong, which its guards stop: kept sortable)
  }
  return speed;
}

// Each element's margin [m] for a build at `skin`.
std::vector<double> element_margins(const ParticleSystem& ps, double skin) {
  const double narrow = 0.5 * skin;
  std::vector<double> margin = element_speeds(ps);
  if (margin.empty()) return margin;
  std::vector<double> sorted = margin;
  const auto q = static_cast<std::ptrdiff_t>(wide_quantile * static_cast<double>(sorted.size() - 1));
  std::nth_element(sorted.begin(), sorted.begin() + q, sorted.end());
  const double typical = sorted[static_cast<std::size_t>(q)];  // [m/s]
  for (double& m : margin) {
    const double times = typical > 0.0 ? m / typical : (m > 0.0 ? wide_margin_most : 1.0);
    m = times >= wide_speed_least ? narrow * std::min(times, wide_margin_most) : narrow;
  }
  return margin;
}

// The skin [m] that makes a step cheapest, given the list of skin s0 that lasted `interval`
// steps (docs/engine.md, the adaptive skin). The list's pairs at skin s are modelled as
// T + E s / s0 (T touching now, E the others) and the steps between builds as interval s / s0
// (the fastest element crosses half the skin at a steady speed), so a step costs
//   T + E s / s0 + (c_e N + c_p (T + E s / s0)) s0 / (interval s)   pair tests,
// least at s = s0 sqrt((c_e N + c_p T) / (interval E)). Only counts enter: every thread count
// and a restarted run choose the same skins.
double cheapest_skin(const NeighborList& neighbors, const ContactSums& sums, std::size_t elements,
                     std::uint64_t interval, const SkinControl& skin) {
  const double s0 = neighbors.skin();
  const std::size_t pairs = neighbors.pairs();
  // (the flags of a list that no contact stage has seen yet are all 1: then none is counted)
  std::size_t touching = 0;
  if (sums.active_build == neighbors.builds() && sums.pair_active.size() == pairs) {
    for (const std::uint8_t a : sums.pair_active) touching += a;
  }
  const double others = static_cast<double>(pairs - std::min(touching, pairs));
  const double build =
      build_cost_per_element * static_cast<double>(elements) + build_cost_per_pair * static_cast<double>(touching);
  const double best = others > 0.0 ? s0 * std::sqrt(build / (static_cast<double>(interval) * others))
                                   : std::numeric_limits<double>::infinity();
  return std::clamp(best, std::max(skin.least, s0 / skin_step_most), std::min(skin.most, s0 * skin_step_most));
}

// Sets the skin for a build that motion made due.
void adapt_skin(World& w, std::uint64_t interval) {
  if (!(w.skin.most > w.skin.least) || interval == 0) return;
  w.neighbors.set_skin(cheapest_skin(w.neighbors, w.sums, w.particles.spheres(), interval, w.skin));
}

// Whether a skin wider than the least, after `elapsed` steps without a build, is worth a build
// of its own at a narrower one (checked at 160, 320, 640, ... steps: the count is cheap but
// not free), and that skin.
bool narrower_skin(const World& w, std::uint64_t elapsed, double& narrower) {
  if (!(w.skin.most > w.skin.least) || !(w.neighbors.skin() > w.skin.least) || elapsed % skin_check_steps != 0 ||
      !std::has_single_bit(elapsed / skin_check_steps)) {  // (0 has no single bit)
    return false;
  }
  narrower = cheapest_skin(w.neighbors, w.sums, w.particles.spheres(), elapsed, w.skin);
  return narrower * skin_narrow_least <= w.neighbors.skin();
}

// Bodies in the order of the cells of a grid (z-major, a cube of 1024 cells a side), so that
// neighbours in space become neighbours in memory; ties by stable id.
void spatial_sort(ParticleSystem& ps, ContactSums& sums, double skin) {
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
  // The bodies' last forces follow them (between steps a removal sorts); part-contact
  // histories follow the spheres' ids (find_part_candidates).
  permute_body_sums(sums, ps.permute(order));
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
  std::vector<std::uint32_t> part, id, history_start;
  std::vector<double> history;
  OldCandidates(PartCandidates& pc, std::span<const std::uint32_t> sphere_ids)
      : first(sphere_ids.empty() ? 0 : *std::max_element(sphere_ids.begin(), sphere_ids.end()) + 1, UINT32_MAX),
        part(std::move(pc.part)),
        id(std::move(pc.sphere_id)),
        history_start(std::move(pc.history_start)),
        history(std::move(pc.history)) {
    for (std::size_t c = id.size(); c-- > 0;) {
      if (id[c] < first.size()) first[id[c]] = static_cast<std::uint32_t>(c);
    }
  }
  // The slots in use of (id, w), if it had any, in their order, into `to`
  // (room for max_part_touches slots of slot_size values); returns their count.
  std::size_t carry(std::uint32_t sphere_id, std::uint32_t w, std::size_t slot_size, double* to) const {
    std::size_t used = 0;
    for (std::size_t c = sphere_id < first.size() ? first[sphere_id] : UINT32_MAX; c < id.size() && id[c] == sphere_id;
         ++c) {
      if (part[c] != w) continue;
      for (std::size_t k = history_start[c]; k < history_start[c + 1]; ++k) {
        const double* slot = history.data() + k * slot_size;
        if (history_slot_in_use(slot)) std::copy_n(slot, slot_size, to + used++ * slot_size);
      }
    }
    return used;
  }
};

// History slots for a candidate with `faces` faces within reach and `carried` slots in use:
// each face gives at most one touch, and a touch that matches no stored normal takes a free
// slot (contact_stage.cpp, history_slot). One face: one touch a step, so one slot (or as many
// as are carried, among which its first touch picks the closest normal); more faces: all.
std::size_t history_slots(std::size_t faces, std::size_t carried) {
  return faces == 1 ? std::max<std::size_t>(carried, 1) : static_cast<std::size_t>(max_part_touches);
}

// The sphere-part candidates: no element moves more than its margin between builds, and a
// build is due when a part has moved half the skin (move_parts), so a sphere further than its
// margin and half the skin from a face cannot reach it before the next build.
void find_part_candidates(const ParticleSystem& ps, std::span<const Part> parts, std::span<PartGeometry> geometry,
                          const NeighborList& neighbors, PartCandidates& pc) {
  const std::size_t n_s = ps.spheres();
  const std::size_t slot_size = 3 + static_cast<std::size_t>(neighbors.history_size());
  const OldCandidates old(pc, ps.sphere_id);
  pc.start.assign(n_s + 1, 0);
  pc.part.clear();
  pc.sphere.clear();
  pc.sphere_id.clear();
  pc.face_start.assign(1, 0);
  pc.faces.clear();
  pc.face_distance.clear();
  pc.history_start.assign(1, 0);
  pc.history.clear();
  std::vector<std::uint32_t> near;
  std::vector<double> carried(max_part_touches * slot_size);
  for (std::size_t s = 0; s < n_s; ++s) {
    // (with the margin half the skin, r + skin exactly)
    const double reach = ps.radius[s] + (neighbors.margin(s) + 0.5 * neighbors.skin());
    for (std::size_t w = 0; w < parts.size(); ++w) {
      if (!parts[w].enabled) continue;
      const Vec3 p = transpose_times(geometry[w].rotation, ps.sphere_position[s] - parts[w].pose.position);
      if (!add_near_faces(geometry[w], p, reach, near, pc)) continue;
      pc.face_start.push_back(static_cast<std::uint32_t>(pc.faces.size()));
      pc.part.push_back(static_cast<std::uint32_t>(w));
      pc.sphere.push_back(static_cast<std::uint32_t>(s));
      pc.sphere_id.push_back(ps.sphere_id[s]);
      const std::size_t in_use = old.carry(ps.sphere_id[s], static_cast<std::uint32_t>(w), slot_size, carried.data());
      const std::size_t faces = pc.face_start.back() - pc.face_start[pc.face_start.size() - 2];
      const std::size_t at = pc.history.size();
      pc.history.resize(at + history_slots(faces, in_use) * slot_size, 0.0);
      std::copy_n(carried.data(), in_use * slot_size, pc.history.data() + at);
      pc.history_start.push_back(static_cast<std::uint32_t>(pc.history.size() / slot_size));
    }
    pc.start[s + 1] = static_cast<std::uint32_t>(pc.part.size());
  }
  pc.history.shrink_to_fit();  // (grown a candidate at a time: up to twice its size)
  pc.reaction.assign(2 * pc.part.size(), Vec3{});
  pc.touches.assign(pc.part.size(), 0);
  for (PartGeometry& pg : geometry) pg.moved = 0.0;
  pc.stale = false;
}

// Runs of whole elements with about 256 pairs and part candidates each (with pair batches of
// 64, 3% faster than runs of 128; 512 was no faster): a fixed split (the thread count plays no
// part), and each element's own sums are taken in one chunk.
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

// The most an element has moved past its margin since the last build (NeighborList::excess2)
// [m2]: after changes from outside, which the drift did not measure. An element added since
// the build has an infinite one.
double measure_displacements(const ParticleSystem& ps, const NeighborList& neighbors) {
  const auto& x = ps.sphere_position;
  const auto n = static_cast<std::ptrdiff_t>(x.size());
  double worst = -std::numeric_limits<double>::infinity();
#pragma omp parallel for schedule(static) reduction(max : worst) if (n > parallel_threshold)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const auto e = static_cast<std::size_t>(i);
    worst = std::max(worst, neighbors.excess2(e, neighbors.displacement2(e, x[e])));
  }
  return worst;
}

}  // namespace

void rebuild_neighbors(World& w, bool adapt) {
  if (adapt) adapt_skin(w, w.steps - w.skin.last_build_step);
  w.skin.last_build_step = w.steps;
  const int sort_every = w.settings.sort_every;
  if (sort_every > 0 && w.neighbors.builds() % static_cast<std::size_t>(sort_every) == 0) {
    spatial_sort(w.particles, w.sums, w.neighbors.skin());
  }
  const auto& ps = w.particles;
  w.neighbors.build(ps.sphere_position, ps.radius, ps.owner, ps.sphere_id, element_margins(ps, w.neighbors.skin()));
  find_part_candidates(ps, w.parts, w.geometry, w.neighbors, w.candidates);
  split_into_chunks(ps.spheres(), w.neighbors, w.candidates, w.sums.chunk_start);
}

void update_neighbors(World& w) {
  bool due = w.displacements == Displacements::past_skin, moved = due;
  if (w.displacements == Displacements::unknown) {
    const double worst = measure_displacements(w.particles, w.neighbors);
    due = w.neighbors.needs_rebuild(worst);
    // (not motion: the first build, or elements added since the last)
    moved = due && std::isfinite(worst) && w.neighbors.builds() > 0;
  }
  // A wide skin is narrowed without waiting for motion to make a build due, which is rare once
  // the particles rest: a bed that settles after a flow soon runs at the narrowest skin again.
  if (double narrower = 0.0;
      !w.candidates.stale && !due && narrower_skin(w, w.steps - w.skin.last_build_step, narrower)) {
    w.neighbors.set_skin(narrower);
    rebuild_neighbors(w, false);
    return;
  }
  if (w.candidates.stale || due) rebuild_neighbors(w, moved);
}

}  // namespace bushel::engine
