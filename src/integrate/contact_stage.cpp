// The contact stage: every sphere-sphere and sphere-part contact of a step, in parallel over
// fixed chunks of elements (each about 256 pairs and part candidates). Every element sums its
// own pairs (as first element) and its nearby parts (part_contact.hpp: one contact per touch
// of a part's surface) in the chunk's scratch; the share of each pair's second element goes
// to the pair's slot, or straight to the element where one thread has all of its pairs as
// second. A chunk's end takes the totals of the bodies it completes (ContactSums). The contact law
// runs over batches of contacts at once (contact_batch.hpp); the rolling model is a template
// parameter, so the loop is compiled once per model.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "bushel/contact/contact_batch.hpp"
#include "bushel/core/parallel.hpp"
#include "bushel/geometry/part_contact.hpp"
#include "stages.hpp"

#ifdef BUSHEL_HAVE_OPENMP
#include <omp.h>
#endif

namespace bushel::engine {
namespace {

Vec3 load3(const double* h) { return {h[0], h[1], h[2]}; }
void store3(double* h, const Vec3& v) { h[0] = v.x, h[1] = v.y, h[2] = v.z; }
double min_moment(const Vec3& i) { return std::min({i.x, i.y, i.z}); }
double max_component(const Vec3& i) { return std::max({i.x, i.y, i.z}); }

// Sphere-part contacts on their way through the contact law: the law's inputs in SoA form,
// and per contact what the rolling model, the torques and the result slots need.
struct LaneExtra {
  std::uint32_t element;  // the sphere (side i), whose own sums take the force
  std::uint32_t item;     // the part candidate, whose reaction takes the rest
  double* history;        // tangential displacement, then the rolling model's values
  Vec3 arm_i, arm_j;      // contact point minus the body's centre of mass, and minus the part origin [m]
  Vec3 omega_i, omega_j;  // [rad/s], set only for rolling models that use them
  double arm_i_len, inertia_r, mu_r;
};

struct PartLanes {
  ContactBatch batch;
  std::array<LaneExtra, ContactBatch::capacity> extra;

  // The next contact's extra fields, filled in place (copying a whole LaneExtra stalls).
  LaneExtra& next() { return extra[static_cast<std::size_t>(batch.size)]; }
  // Adds the next contact; its extra fields must be filled already. The tangential
  // displacement is read from its history.
  void push(const Vec3& n, double overlap, const Vec3& v_rel, double r_star, double m_star, double compliance,
            const PairCoefficients& c) {
    ContactBatch& b = batch;
    const int k = b.size++;
    b.nx[k] = n.x, b.ny[k] = n.y, b.nz[k] = n.z;
    b.overlap[k] = overlap;
    b.vx[k] = v_rel.x, b.vy[k] = v_rel.y, b.vz[k] = v_rel.z;
    b.r_star[k] = r_star;
    b.m_star[k] = m_star;
    b.compliance[k] = compliance;
    b.law.set(k, c);
    const double* history = extra[static_cast<std::size_t>(k)].history;
    b.xi_x[k] = history[0], b.xi_y[k] = history[1], b.xi_z[k] = history[2];
  }
};

// Sphere-sphere contacts: the batch (which does their kinematics too), the pair and element
// of each, and the touching pairs of the chunk at hand.
struct PairLanes {
  PairBatch batch;
  std::array<std::uint32_t, PairBatch::capacity> element, pair;
  std::array<std::uint32_t, PairBatch::capacity> coefficient;  // index of the pair's coefficients
  std::vector<std::uint32_t> touching, ended;
};
// The rare cases of a batch, kept out of the loop that fills it (a call there would make the
// compiler keep that loop's pointers in memory): lanes whose coefficients differ from lane
// 0's, and elements that are not at their bodies' centres of mass (their offsets, and their
// bodies' largest inverse moments for the damping bound).
[[gnu::noinline, gnu::cold]] void set_coefficients(PairLanes& pl, const PairCoefficients* coefficients) {
  PairBatch& b = pl.batch;
  for (int k = 1; k < b.size; ++k) {  // (lane 0's are set already)
    b.law.set(k, coefficients[pl.coefficient[static_cast<std::size_t>(k)]]);
  }
}
[[gnu::noinline, gnu::cold]] void set_offsets(PairLanes& pl, std::span<const Vec3> x_el, std::span<const Vec3> x_b,
                                              std::span<const Vec3> type_inverse_inertia,
                                              std::span<const std::uint32_t> owner,
                                              std::span<const std::uint32_t> species,
                                              std::span<const std::uint32_t> sphere_count,
                                              std::span<const std::uint32_t> second) {
  PairBatch& b = pl.batch;
  for (int k = 0; k < b.size; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const std::uint32_t i = pl.element[kk], j = second[pl.pair[kk]], bi = owner[i], bj = owner[j];
    // (a lone sphere's centre is its centre of mass: its body position is not read)
    const Vec3 oi = sphere_count[bi] == 1 ? Vec3{} : x_el[i] - x_b[bi];
    const Vec3 oj = sphere_count[bj] == 1 ? Vec3{} : x_el[j] - x_b[bj];
    b.oix[k] = oi.x, b.oiy[k] = oi.y, b.oiz[k] = oi.z;
    b.ojx[k] = oj.x, b.ojy[k] = oj.y, b.ojz[k] = oj.z;
    b.ji[k] = max_component(type_inverse_inertia[species[i]]),
    b.jj[k] = max_component(type_inverse_inertia[species[j]]);
  }
}

struct Workspace {
  PairLanes pairs;
  PartLanes parts;
  std::vector<ElementSums> own;    // the chunk's elements' own sums
  std::vector<ElementSums> carry;  // those of a body that goes on in the thread's next chunk, from its first
};

// Everything the contact stage reads and writes, as plain views. Each chunk works on its own
// copy: a byte store (pair_active) may alias any vector's internals or any shared variable,
// so through the vectors, or through variables shared by an OpenMP region, the compiler would
// reload every data pointer after it; from a private copy it keeps them in registers.
struct ContactViews {
  // bodies [b]
  std::span<const Vec3> x_b, v_b, w_b;
  // types [species of an element = body_type of its owner]
  std::span<const double> type_mass;
  std::span<const Vec3> type_inertia, type_inverse_inertia;
  std::span<const std::uint32_t> sphere_count, first_sphere;
  // sphere elements [s]
  std::span<const Vec3> x_el;
  std::span<const double> radius;
  std::span<const std::uint32_t> owner, species;
  // pairs [p] of the neighbour list, with their contact-law history and result slots
  std::span<const std::uint32_t> first, second;
  double* history;
  std::span<std::uint8_t> active;
  // slots of the second elements not summed directly (ContactSums)
  std::span<Vec3> pair_force, pair_torque_j;
  std::span<double> pair_cdt_j;
  std::span<const std::uint32_t> slots_of, slot_pair;
  const NeighborList* neighbors;
  // per element sums (ContactSums): the chunk's own sums (element e0 + k at k), the shares
  // as second element, the deferred elements and their own sums
  std::span<ElementSums> own;
  std::uint32_t e0;
  std::span<const std::uint8_t> second_direct;
  std::span<ElementSums> element;
  std::span<const std::uint32_t> deferred, chunk_deferred;
  std::span<ElementSums> deferred_own;
  Vec3 gravity;  // [m/s2]
  // sphere-part candidates [c] (PartCandidates) and the parts [w]
  std::span<const std::uint32_t> part_start, sphere_of_candidate, part_of_candidate, candidate_face_start,
      candidate_faces;
  std::span<const double> candidate_face_distance;
  std::span<const std::uint32_t> history_start;
  double* part_history;
  std::span<std::uint8_t> candidate_touches;
  std::span<Vec3> part_reaction;
  std::span<const Part> parts;
  std::span<const PartGeometry> geometry;
  // the law
  const PairCoefficients* coefficients;  // [species i * n_species + species j]
  std::size_t n_species, n_types;
  int h;                // history values per pair
  double dt;            // [s]
  double damping_rate;  // largest tangential damping over the contact's sliding mass [1/s] (contact_batch.hpp)
};

struct ChunkResult {
  double max_ratio = 0.0;    // largest overlap over the smaller radius
  std::size_t touching = 0;  // sphere-sphere contacts
  double force_sum = 0.0;    // their force magnitudes, summed in pair order [N]
};

// The deepest sphere-sphere overlap of a chunk, as overlap and the smaller radius [m], compared
// by cross-multiplying.
struct Deepest {
  double overlap = 0.0, radius = 1.0;
};

// The slot of pair p for its second element j (not summed directly): j's slots list its
// pairs as second, which are few and ascending.
std::size_t slot_of(const ContactViews& v, std::size_t p, std::uint32_t j) {
  const auto pairs = v.slot_pair.begin();
  return static_cast<std::size_t>(std::lower_bound(pairs + v.slots_of[j], pairs + v.slots_of[j + 1], p) - pairs);
}

// Which of pairs [p0, p1) touch, into pl.touching (returns their count), without a branch on
// it: about a third of the pairs in the list do not, in no predictable order. A contact that
// ended has its history zeroed (after the loop, which stays free of calls).
[[gnu::always_inline]] inline std::size_t find_touching(const ContactViews& v, std::size_t p0, std::size_t p1,
                                                        PairLanes& pl) {
  pl.touching.resize(p1 - p0);
  pl.ended.resize(p1 - p0);
  std::size_t n_touching = 0, n_ended = 0;
  // Plain local pointers: the byte store to `active` may alias anything whose address
  // escaped (the views, the workspace's vectors), so through those the compiler reloaded
  // nine pointers from memory on every pair.
  const std::uint32_t *const first_of = v.first.data(), *const second_of = v.second.data();
  const double* const radius_of = v.radius.data();
  const std::uint32_t* const owner_of = v.owner.data();
  const Vec3* const x_of = v.x_el.data();
  std::uint32_t *const touching = pl.touching.data(), *const ended = pl.ended.data();
  std::uint8_t* const active_of = v.active.data();
  const double* const history_of = v.history;
  const auto stride = static_cast<std::size_t>(v.h);
  for (std::size_t p = p0; p < p1; ++p) {
    const std::uint32_t i = first_of[p], j = second_of[p];
    const double reach = radius_of[i] + radius_of[j];
    const std::uint8_t touch = norm2(x_of[j] - x_of[i]) < reach * reach ? 1 : 0;
    touching[n_touching] = static_cast<std::uint32_t>(p);
    n_touching += touch;
    ended[n_ended] = static_cast<std::uint32_t>(p);
    n_ended += active_of[p] > touch ? 1 : 0;
    active_of[p] = touch;
    // The chunk's histories (a few kB, in pair order) are read by the batch fill below and
    // missed the cache there; fetched while this loop runs, they are in by then.
    __builtin_prefetch(history_of + p * stride, 1);
    // The second element of a pair a little ahead: its position and radius are this
    // loop's only scattered reads, its owner the batch fill's first (bench/results/engine-tuning.md).
    if (constexpr std::size_t ahead_by = 16; p + ahead_by < p1) {
      const std::uint32_t ahead = second_of[p + ahead_by];
      __builtin_prefetch(x_of + ahead);
      __builtin_prefetch(radius_of + ahead);
      __builtin_prefetch(owner_of + ahead);
    }
  }
  for (std::size_t e = 0; e < n_ended; ++e) std::fill_n(v.history + std::size_t{pl.ended[e]} * stride, v.h, 0.0);
  return n_touching;
}

// Touching pairs [t0, t0 + n) of pl.touching into the batch, side i = the pair's first
// element. The coefficients are stored once while every pair of the batch has the same (one
// material, the usual case), the offsets not at all while every element is a lone sphere.
[[gnu::always_inline]] inline void fill_pair_batch(const ContactViews& v, std::size_t t0, int n, PairLanes& pl) {
  PairBatch& pb = pl.batch;
  const auto ns = static_cast<std::uint32_t>(v.n_species);  // (a handful: the species table is square)
  const std::uint32_t co0 = v.species[v.first[pl.touching[t0]]] * ns + v.species[v.second[pl.touching[t0]]];
  bool lone = true, uniform = true;
  for (int k = 0; k < n; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const std::uint32_t p = pl.touching[t0 + kk];
    const std::uint32_t i = v.first[p], j = v.second[p], bi = v.owner[i], bj = v.owner[j];
    // (read in place: copies of the Vec3s went through the stack)
    const Vec3 &xi = v.x_el[i], &xj = v.x_el[j], &vi = v.v_b[bi], &vj = v.v_b[bj], &wi = v.w_b[bi], &wj = v.w_b[bj];
    pb.dx[k] = xj.x - xi.x, pb.dy[k] = xj.y - xi.y, pb.dz[k] = xj.z - xi.z;
    pb.ri[k] = v.radius[i], pb.rj[k] = v.radius[j];
    pb.vix[k] = vi.x, pb.viy[k] = vi.y, pb.viz[k] = vi.z;
    pb.vjx[k] = vj.x, pb.vjy[k] = vj.y, pb.vjz[k] = vj.z;
    pb.wix[k] = wi.x, pb.wiy[k] = wi.y, pb.wiz[k] = wi.z;
    pb.wjx[k] = wj.x, pb.wjy[k] = wj.y, pb.wjz[k] = wj.z;
    pb.mi[k] = v.type_mass[v.species[i]], pb.mj[k] = v.type_mass[v.species[j]];
    const double* hist = v.history + std::size_t{p} * static_cast<std::size_t>(v.h);
    pb.xi_x[k] = hist[0], pb.xi_y[k] = hist[1], pb.xi_z[k] = hist[2];
    // j's sums, which finish_pairs adds to after the batch is solved, miss the cache otherwise.
    __builtin_prefetch(&v.element[j], 1);
    // And j's body position, which set_offsets reads for clumps.
    __builtin_prefetch(&v.x_b[bj]);
    const std::uint32_t co = v.species[i] * ns + v.species[j];
    pl.coefficient[kk] = co;
    uniform &= co == co0;
    lone &= (v.sphere_count[bi] == 1) & (v.sphere_count[bj] == 1);
    pl.element[kk] = i;
    pl.pair[kk] = p;
  }
  pb.size = n;
  pb.centred = lone;
  pb.uniform = uniform;
  pb.law.set(0, v.coefficients[co0]);
  if (!uniform) set_coefficients(pl, v.coefficients);
  if (!lone) set_offsets(pl, v.x_el, v.x_b, v.type_inverse_inertia, v.owner, v.species, v.sphere_count, v.second);
}

// Solves the batch of pairs, updates their histories, applies rolling model R; side i adds to
// its element's own sums (in pair order), side j's share to j's sum as second element (or,
// where other threads have some of j's pairs, to the pair's slot).
template <class Rolling>
[[gnu::always_inline]] inline void finish_pairs(const ContactViews& v, PairLanes& pl, ChunkResult& r,
                                                Deepest& deepest) {
  PairBatch& pb = pl.batch;
  solve(pb, v.dt, v.damping_rate);
  for (int k = 0; k < pb.size; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const std::uint32_t i = pl.element[kk], p = pl.pair[kk], j = v.second[p];
    double* hist = v.history + std::size_t{p} * static_cast<std::size_t>(v.h);
    hist[0] = pb.xi_x[k], hist[1] = pb.xi_y[k], hist[2] = pb.xi_z[k];
    Vec3 spring = Rolling::history_size ? load3(hist + 3) : Vec3{};
    double inertia_r = 0.0;
    if constexpr (Rolling::uses_inertia) {
      const double ii = min_moment(v.type_inertia[v.species[i]]) + pb.mi[k] * pb.arm_i[k] * pb.arm_i[k];
      const double ij = min_moment(v.type_inertia[v.species[j]]) + pb.mj[k] * pb.arm_j[k] * pb.arm_j[k];
      inertia_r = ii * ij / (ii + ij);
    }
    const RollingOutput roll = Rolling::torque({.normal = {pb.nx[k], pb.ny[k], pb.nz[k]},
                                                .omega_i = {pb.wix[k], pb.wiy[k], pb.wiz[k]},
                                                .omega_j = {pb.wjx[k], pb.wjy[k], pb.wjz[k]},
                                                .arm_i = pb.arm_i[k],
                                                .arm_j = pb.arm_j[k],
                                                .r_star = pb.r_star[k],
                                                .normal_force = pb.normal_force[k],
                                                .normal_stiffness = pb.normal_stiffness[k],
                                                .overlap = pb.overlap[k],
                                                .mu_r = v.coefficients[pl.coefficient[kk]].rolling_friction,
                                                .inertia_r = inertia_r,
                                                .dt = v.dt},
                                               spring);
    if constexpr (Rolling::history_size > 0) store3(hist + 3, spring);
    const Vec3 f{pb.fx[k], pb.fy[k], pb.fz[k]};
    Vec3 t_i{pb.tix[k], pb.tiy[k], pb.tiz[k]}, t_j{pb.tjx[k], pb.tjy[k], pb.tjz[k]};
    if constexpr (Rolling::has_torque) t_i += roll.torque_i, t_j += roll.torque_j;
    ElementSums& sums_i = v.own[i - v.e0];
    sums_i.force += f;
    r.force_sum += norm(f);
    sums_i.torque += t_i;
    sums_i.cdt += roll.cdt_i;
    if (v.second_direct[j]) {  // this thread has all of j's pairs as second: sum in pair order
      ElementSums& sums_j = v.element[j];
      sums_j.force -= f;
      sums_j.torque += t_j;
      sums_j.cdt += roll.cdt_j;
    } else {  // the gather sums j's slots in the same order
      const std::size_t slot = slot_of(v, p, j);
      v.pair_force[slot] = f;
      v.pair_torque_j[slot] = t_j;
      v.pair_cdt_j[slot] = roll.cdt_j;
    }
    const double smaller = std::min(pb.ri[k], pb.rj[k]);
    if (pb.overlap[k] * deepest.radius > deepest.overlap * smaller) deepest = {pb.overlap[k], smaller};
  }
  r.touching += static_cast<std::size_t>(pb.size);
}

// The sphere-sphere contacts of pairs [p0, p1) (whose first elements are the chunk's).
template <class Rolling>
[[gnu::always_inline]] inline void pair_contacts(const ContactViews& v, std::size_t p0, std::size_t p1, PairLanes& pl,
                                                 ChunkResult& r) {
  Deepest deepest;
  const std::size_t n_touching = find_touching(v, p0, p1, pl);
  for (std::size_t t0 = 0; t0 < n_touching; t0 += PairBatch::capacity) {
    const int n = static_cast<int>(std::min<std::size_t>(PairBatch::capacity, n_touching - t0));
    fill_pair_batch(v, t0, n, pl);
    finish_pairs<Rolling>(v, pl, r, deepest);
  }
  r.max_ratio = deepest.overlap / deepest.radius;
}

// The slot of a candidate's n_slots history slots (each [normal (3), law history]) that a
// contact with this normal takes: the closest stored normal within 60 degrees, else a free
// one, else any unused (cleared). Keyed by the normal, a contact sliding across the
// triangles of one part keeps its history.
[[gnu::always_inline]] inline int history_slot(double* slots, int n_slots, std::size_t slot_size, const Vec3& normal,
                                               const std::array<bool, max_part_touches>& used) {
  int slot = -1;
  double best = 0.5;
  for (int j = 0; j < n_slots; ++j) {
    const double c = dot(load3(slots + j * slot_size), normal);
    if (!used[static_cast<std::size_t>(j)] && c > best) best = c, slot = j;
  }
  for (int j = 0; j < n_slots && slot < 0; ++j) {
    if (!used[static_cast<std::size_t>(j)] && !history_slot_in_use(slots + j * slot_size)) slot = j;
  }
  for (int j = 0; j < n_slots && slot < 0; ++j) {
    if (!used[static_cast<std::size_t>(j)]) slot = j, std::fill_n(slots + j * slot_size, slot_size, 0.0);
  }
  return slot;
}

// A part candidate's contacts (up to max_part_touches) into the batch with side i = the
// sphere. Returns the largest overlap ratio, or -1 if nothing touches.
template <class Rolling>
[[gnu::always_inline]] inline double visit_part(const ContactViews& v, std::size_t cw, PartLanes& lanes) {
  const std::uint32_t s = v.sphere_of_candidate[cw], w = v.part_of_candidate[cw];
  const std::uint32_t b = v.owner[s];
  const PartGeometry& pg = v.geometry[w];
  const Part& part = v.parts[w];
  const Vec3 origin = part.pose.position;
  std::array<PartTouch, max_part_touches> touches;
  const std::size_t f0 = v.candidate_face_start[cw], nf = v.candidate_face_start[cw + 1] - f0;
  // Faces further than the sphere and the part have moved since the build are skipped.
  const double moved = nf > 1 ? std::sqrt(v.neighbors->displacement2(s, v.x_el[s])) + pg.moved : 0.0;
  const int n =
      part_touches(pg.faces, v.candidate_faces.subspan(f0, nf), transpose_times(pg.rotation, v.x_el[s] - origin),
                   v.radius[s], touches, v.candidate_face_distance.subspan(f0, nf), moved);
  const std::size_t slot_size = 3 + static_cast<std::size_t>(v.h);
  double* slots = v.part_history + std::size_t{v.history_start[cw]} * slot_size;
  const auto n_slots = static_cast<int>(v.history_start[cw + 1] - v.history_start[cw]);
  v.part_reaction[2 * cw] = v.part_reaction[2 * cw + 1] = Vec3{};
  v.candidate_touches[cw] = static_cast<std::uint8_t>(n);
  std::array<bool, max_part_touches> used{};
  double max_ratio = -1.0;
  for (int k = 0; k < n; ++k) {
    const PartTouch& t = touches[static_cast<std::size_t>(k)];
    const Vec3 normal = pg.rotation * t.normal, point = origin + pg.rotation * t.point;
    const int slot = history_slot(slots, n_slots, slot_size, normal, used);
    used[static_cast<std::size_t>(slot)] = true;
    double* hist = slots + static_cast<std::size_t>(slot) * slot_size;
    store3(hist, normal);
    const Vec3 arm = point - v.x_b[b];
    const Vec3 v_part = part.twist.velocity + cross(part.twist.angular_velocity, point - origin);
    const Vec3 v_rel = v.v_b[b] + cross(v.w_b[b], arm) - v_part;
    const double arm_len = norm(arm);
    const PairCoefficients& co = v.coefficients[v.species[s] * v.n_species + v.n_types + w];
    LaneExtra& e = lanes.next();
    e.element = s;
    e.item = static_cast<std::uint32_t>(cw);
    e.history = hist + 3;
    e.arm_i = arm;
    e.arm_j = point - origin;  // for the reaction's torque about the part origin
    if constexpr (Rolling::uses_spin) {
      e.omega_i = v.w_b[b];
      e.omega_j = part.twist.angular_velocity;
    }
    e.arm_i_len = arm_len;
    const double mass = v.type_mass[v.species[s]];
    e.inertia_r = min_moment(v.type_inertia[v.species[s]]) + mass * arm_len * arm_len;
    e.mu_r = co.rolling_friction;
    lanes.push(normal, t.overlap, v_rel, v.radius[s], mass,
               1.0 / mass + arm_len * arm_len * max_component(v.type_inverse_inertia[v.species[s]]), co);
    max_ratio = std::max(max_ratio, t.overlap / v.radius[s]);
  }
  for (int j = 0; j < n_slots; ++j) {  // contacts that ended start afresh
    double* slot = slots + j * slot_size;
    if (!used[static_cast<std::size_t>(j)] && history_slot_in_use(slot)) std::fill_n(slot, slot_size, 0.0);
  }
  return max_ratio;
}

// Solves the batch, updates the histories, applies rolling model R; the sphere adds to its
// element's own sums (after its pairs), the part candidate's reaction takes the rest (a
// candidate may have several contacts).
template <class Rolling>
[[gnu::always_inline]] inline void finish_parts(const ContactViews& v, PartLanes& lanes) {
  ContactBatch& b = lanes.batch;
  solve(b, v.dt, v.damping_rate);
  for (int k = 0; k < b.size; ++k) {
    const LaneExtra& e = lanes.extra[static_cast<std::size_t>(k)];
    e.history[0] = b.xi_x[k], e.history[1] = b.xi_y[k], e.history[2] = b.xi_z[k];
    Vec3 spring = Rolling::history_size ? load3(e.history + 3) : Vec3{};
    const RollingOutput roll = Rolling::torque({.normal = {b.nx[k], b.ny[k], b.nz[k]},
                                                .omega_i = e.omega_i,
                                                .omega_j = e.omega_j,
                                                .arm_i = e.arm_i_len,
                                                .arm_j = 0.0,
                                                .r_star = b.r_star[k],
                                                .normal_force = b.normal_force[k],
                                                .normal_stiffness = b.normal_stiffness[k],
                                                .overlap = b.overlap[k],
                                                .mu_r = e.mu_r,
                                                .inertia_r = e.inertia_r,
                                                .dt = v.dt},
                                               spring);
    if constexpr (Rolling::history_size > 0) store3(e.history + 3, spring);
    const Vec3 f{b.fx[k], b.fy[k], b.fz[k]};
    ElementSums& sums = v.own[e.element - v.e0];
    sums.force += f;
    sums.torque += cross(e.arm_i, f) + roll.torque_i;
    sums.cdt += roll.cdt_i;
    v.part_reaction[2 * std::size_t{e.item}] -= f;
    v.part_reaction[2 * std::size_t{e.item} + 1] += cross(e.arm_j, -f) - roll.torque_i;
  }
  b.size = 0;
}

// The end of chunk k, elements [e0, e1): the totals of the bodies it finishes, in the
// gather's order (body_totals); a body that goes on in the next chunk (the same thread's)
// keeps its own sums so far in the workspace; the deferred elements' own sums are kept for
// the gather.
void finish_bodies(const ContactViews& v, std::size_t k, std::uint32_t e0, std::uint32_t e1, Workspace& work) {
  std::size_t d = v.chunk_deferred[k];
  const std::size_t d_end = v.chunk_deferred[k + 1];
  std::uint32_t s0 = 0;               // the body's first element
  const ElementSums* from = nullptr;  // its own sums, from its first element's
  const auto own = [&from, &s0](std::uint32_t s) -> const ElementSums& { return from[s - s0]; };
  const auto second = [&v](std::uint32_t s) -> const ElementSums& { return v.element[s]; };
  for (std::uint32_t s = e0; s < e1;) {
    if (d < d_end && v.deferred[d] == s) {
      v.deferred_own[d++] = v.own[s - e0];
      ++s;
      continue;
    }
    const std::uint32_t b = v.owner[s], n = v.sphere_count[b];
    s0 = v.first_sphere[b];  // (before e0: carried in from the last chunk)
    if (s0 + n > e1) {
      if (s0 >= e0) work.carry.clear();
      work.carry.insert(work.carry.end(), v.own.begin() + (std::max(s0, e0) - e0), v.own.end());
      break;
    }
    if (s0 < e0) {
      work.carry.insert(work.carry.end(), v.own.begin(), v.own.begin() + (s0 + n - e0));
      from = work.carry.data();
    } else {
      from = v.own.data() + (s0 - e0);
    }
    put_totals(v.element, s0, n, body_totals(v.type_mass[v.species[s0]] * v.gravity, s0, n, own, second));
    s = s0 + n;
  }
}

// The contacts of chunk k, elements [e0, e1): their pairs [p0, p1) as first element, then
// their part candidates, into the elements' own sums (the workspace's, zeroed here); then
// the chunk's bodies are finished.
template <class Rolling>
ChunkResult contact_chunk(const ContactViews& views, std::size_t k, std::uint32_t e0, std::uint32_t e1, std::size_t p0,
                          std::size_t p1, Workspace& work) {
  ContactViews v = views;
  work.own.assign(e1 - e0, ElementSums{});
  v.own = work.own;
  v.e0 = e0;
  ChunkResult r;
  pair_contacts<Rolling>(v, p0, p1, work.pairs, r);
  PartLanes& lanes = work.parts;
  for (std::size_t cw = v.part_start[e0]; cw < v.part_start[e1]; ++cw) {
    if (lanes.batch.size + max_part_touches > ContactBatch::capacity) finish_parts<Rolling>(v, lanes);
    r.max_ratio = std::max(r.max_ratio, visit_part<Rolling>(v, cw, lanes));
  }
  finish_parts<Rolling>(v, lanes);
  finish_bodies(v, k, e0, e1, work);
  return r;
}

// Which bodies the contact stage finishes at the end of their last element's chunk: those
// whose elements all lie in one thread's chunks and take all their shares as second from that
// thread, which has summed them by then (a pair's first element comes before its second, and
// a thread takes its chunks in order). The elements of the others are deferred to the gather.
void defer_bodies(ContactSums& sums, const ParticleSystem& ps, std::span<const int> thread_of,
                  std::span<const int> thread_as_second) {
  const std::vector<std::uint32_t>& chunk_start = sums.chunk_start;
  sums.deferred.clear();
  for (std::uint32_t s0 = 0; s0 < ps.spheres();) {
    const std::uint32_t s1 = s0 + ps.sphere_count[ps.owner[s0]];
    bool finished = true;
    for (std::uint32_t s = s0; s < s1; ++s) {
      finished &= thread_of[s] == thread_of[s0] && sums.second_direct[s] &&
                  (thread_as_second[s] < 0 || thread_as_second[s] == thread_of[s]);
    }
    for (std::uint32_t s = s0; s < s1 && !finished; ++s) sums.deferred.push_back(s);
    s0 = s1;
  }
  sums.deferred_own.resize(sums.deferred.size());
  sums.chunk_deferred.resize(chunk_start.size());
  for (std::size_t c = 0; c < chunk_start.size(); ++c) {
    const auto at = std::lower_bound(sums.deferred.begin(), sums.deferred.end(), chunk_start[c]);
    sums.chunk_deferred[c] = static_cast<std::uint32_t>(at - sums.deferred.begin());
  }
}

// An element's shares as second element may be summed by the contact stage itself when one
// thread computes all its pairs as second: that thread meets them in pair order. The others
// (none at one thread; at more, those whose pairs as second fall to two threads, a few near
// the blocks' ends) get a slot per such pair, listed in pair order.
void mark_direct_seconds(ContactSums& sums, const NeighborList& neighbors, const ParticleSystem& ps, int team) {
  const std::size_t n_s = ps.spheres();
  const auto split = sums.shares.bounds();
  std::vector<int> thread_of(n_s, 0);
  for (int t = 0; t < team; ++t) {
    const auto c0 = split[static_cast<std::size_t>(t)], c1 = split[static_cast<std::size_t>(t) + 1];
    std::fill(thread_of.begin() + sums.chunk_start[c0], thread_of.begin() + sums.chunk_start[c1], t);
  }
  const auto first = neighbors.firsts(), second = neighbors.seconds();
  std::fill(sums.second_direct.begin(), sums.second_direct.end(), 1);  // (sized before: views hold it)
  std::vector<int> thread_as_second(n_s, -1);  // the thread of the element's first pair as second
  for (std::size_t p = 0; p < first.size(); ++p) {
    int& t = thread_as_second[second[p]];
    if (t < 0) t = thread_of[first[p]];
    if (t != thread_of[first[p]]) sums.second_direct[second[p]] = 0;
  }
  std::vector<std::uint32_t>& slots_of = sums.slots_of;
  slots_of.assign(n_s + 1, 0);
  for (std::size_t p = 0; p < first.size(); ++p) slots_of[second[p] + 1] += sums.second_direct[second[p]] ? 0 : 1;
  std::partial_sum(slots_of.begin(), slots_of.end(), slots_of.begin());
  const std::uint32_t slots = slots_of[n_s];
  sums.slot_pair.resize(slots);
  std::vector<std::uint32_t> fill(slots_of.begin(), slots_of.end() - 1);
  for (std::size_t p = 0; p < first.size(); ++p) {
    if (!sums.second_direct[second[p]]) sums.slot_pair[fill[second[p]]++] = static_cast<std::uint32_t>(p);
  }
  sums.pair_force.resize(slots);
  sums.pair_torque_j.resize(slots);
  sums.pair_cdt_j.resize(slots);
  defer_bodies(sums, ps, thread_of, thread_as_second);
  sums.direct_build = neighbors.builds();
  sums.direct_team = team;
}

// On a new list every pair counts as touching once, so that where it does not, its history is
// zeroed; from then on only pairs whose contact ends write zeros.
void reset_active_pairs(ContactSums& sums, const NeighborList& neighbors) {
  const std::size_t n_pairs = neighbors.pairs();
  if (neighbors.builds() != sums.active_build) {
    sums.pair_active.assign(n_pairs, 1);
    sums.active_build = neighbors.builds();
  }
}

ContactViews views_of(World& w) {
  auto& ps = w.particles;
  auto& s = w.sums;
  auto& c = w.candidates;
  const double dt = w.settings.dt;
  return {.x_b = ps.position,
          .v_b = ps.velocity,
          .w_b = ps.angular_velocity,
          .type_mass = ps.type_mass(),
          .type_inertia = ps.type_inertia(),
          .type_inverse_inertia = ps.type_inverse_inertia(),
          .sphere_count = ps.sphere_count,
          .first_sphere = ps.first_sphere,
          .x_el = ps.sphere_position,
          .radius = ps.radius,
          .owner = ps.owner,
          .species = ps.species,
          .first = w.neighbors.firsts(),
          .second = w.neighbors.seconds(),
          .history = w.neighbors.all_history().data(),
          .active = s.pair_active,
          .pair_force = s.pair_force,
          .pair_torque_j = s.pair_torque_j,
          .pair_cdt_j = s.pair_cdt_j,
          .slots_of = s.slots_of,
          .slot_pair = s.slot_pair,
          .neighbors = &w.neighbors,
          .own = {},
          .e0 = 0,
          .second_direct = s.second_direct,
          .element = s.element,
          .deferred = s.deferred,
          .chunk_deferred = s.chunk_deferred,
          .deferred_own = s.deferred_own,
          .gravity = w.settings.gravity,
          .part_start = c.start,
          .sphere_of_candidate = c.sphere,
          .part_of_candidate = c.part,
          .candidate_face_start = c.face_start,
          .candidate_faces = c.faces,
          .candidate_face_distance = c.face_distance,
          .history_start = c.history_start,
          .part_history = c.history.data(),
          .candidate_touches = c.touches,
          .part_reaction = c.reaction,
          .parts = w.parts,
          .geometry = w.geometry,
          .coefficients = w.coefficients.size() > 0 ? &w.coefficients(0, 0) : nullptr,
          .n_species = w.coefficients.size(),
          .n_types = ps.types().size(),
          .h = w.neighbors.history_size(),
          .dt = dt,
          .damping_rate = w.settings.tangential_damping_limit / dt};
}

template <class Rolling>
void contacts(World& w) {
  reset_active_pairs(w.sums, w.neighbors);
  double max_ratio = 0.0;
  std::size_t touching = 0;
  ContactSums& sums = w.sums;
  const std::size_t n_chunks = sums.chunk_start.size() - 1;
  std::vector<double>& force_sum = w.diagnostics.chunk_force_sum;
  force_sum.resize(n_chunks);
  int team_used = 1;
#pragma omp parallel reduction(max : max_ratio) reduction(+ : touching) if (static_cast <std::ptrdiff_t>( \
                                                                                w.particles.spheres()) > \
                                                                                parallel_threshold)
  {
    int team = 1, me = 0;
#ifdef BUSHEL_HAVE_OPENMP
    team = omp_get_num_threads(), me = omp_get_thread_num();
#endif
    // The shares as second element are summed from zero: the last step's totals (the bodies'
    // first elements' entries, the others are zero: put_totals) have been read.
    const auto nb = static_cast<std::ptrdiff_t>(w.particles.bodies());
#pragma omp for schedule(static) nowait
    for (std::ptrdiff_t b = 0; b < nb; ++b) {
      sums.element[w.particles.first_sphere[static_cast<std::size_t>(b)]] = {};
    }
    // Each thread takes a block of chunks (ThreadShares), which mark_direct_seconds knows.
#pragma omp single
    {
      const bool split = sums.shares.split(n_chunks, team);
      if (split || sums.direct_build != w.neighbors.builds() || sums.direct_team != team ||
          sums.slots_of.size() != w.particles.spheres() + 1 || sums.chunk_deferred.size() != n_chunks + 1) {
        mark_direct_seconds(sums, w.neighbors, w.particles, team);
      }
      team_used = team;
    }
    const ContactViews views = views_of(w);  // (after the slots are sized, which the single's barrier ensures)
    // Each thread's scratch, kept between steps: allocating and zeroing it every step cost
    // more than the L1 cache holds.
    thread_local std::unique_ptr<Workspace> work;
    if (!work) work = std::make_unique<Workspace>();
    const auto start = std::chrono::steady_clock::now();
    const std::size_t c0 = sums.shares.bounds()[static_cast<std::size_t>(me)];
    const std::size_t c1 = sums.shares.bounds()[static_cast<std::size_t>(me) + 1];
    for (std::size_t c = c0; c < c1; ++c) {
      const std::uint32_t e0 = sums.chunk_start[c], e1 = sums.chunk_start[c + 1];
      const ChunkResult r =
          contact_chunk<Rolling>(views, c, e0, e1, w.neighbors.begin_of(e0), w.neighbors.begin_of(e1), *work);
      max_ratio = std::max(max_ratio, r.max_ratio);
      touching += r.touching;
      force_sum[c] = r.force_sum;
    }
    sums.shares.add_busy(me, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  if (team_used > 1) sums.shares.balance();
  StepDiagnostics& d = w.diagnostics;
  d.pair_force_sum = 0.0;  // (summed in chunk order: the same sum for any thread count)
  for (std::size_t c = 0; c < n_chunks; ++c) d.pair_force_sum += force_sum[c];
  d.max_overlap_ratio = max_ratio;
  d.peak_overlap_ratio = std::max(d.peak_overlap_ratio, max_ratio);
  d.contacts = touching;
}

}  // namespace

void compute_contacts(World& w) {
  std::visit([&w](const auto& model) { contacts<std::decay_t<decltype(model)>>(w); }, w.rolling);
}

}  // namespace bushel::engine
