#include "bushel/integrate/simulation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "bushel/contact/contact_batch.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/core/parallel.hpp"
#include "bushel/geometry/part_contact.hpp"
#include "bushel/integrate/rigid_rotation.hpp"
#include "bushel/integrate/rotation_batch.hpp"
#include "bushel/io/binary_archive.hpp"

#ifdef BUSHEL_HAVE_OPENMP
#include <omp.h>
#endif

namespace bushel {
namespace {

Vec3 load3(const double* h) { return {h[0], h[1], h[2]}; }
void store3(double* h, const Vec3& v) { h[0] = v.x, h[1] = v.y, h[2] = v.z; }
double min_moment(const Vec3& i) { return std::min({i.x, i.y, i.z}); }
double max_component(const Vec3& i) { return std::max({i.x, i.y, i.z}); }
// Equal principal moments (a sphere): L = I omega in any frame, so rotation needs no quaternion work.
bool is_isotropic(const Vec3& i) { return i.x == i.y && i.y == i.z; }

// The adaptive skin (Simulation::rebuild): it widens when a build comes fewer than this many
// steps after the last, narrows when more, by this factor a build, between these shares of
// the largest element radius (0.11 and 0.35 of its diameter).
constexpr std::uint64_t skin_widen_below_steps = 40;
constexpr std::uint64_t skin_narrow_above_steps = 160;
constexpr double skin_factor = 1.25;
constexpr double skin_least_per_radius = 0.22;
constexpr double skin_most_per_radius = 0.70;

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

// Lane k's coefficients, in a pair batch or a contact batch.
template <class Batch>
void store_coefficients(Batch& b, int k, const PairCoefficients& c) {
  b.youngs_modulus[k] = c.youngs_modulus;
  b.stiffness_ratio[k] = c.stiffness_ratio;
  b.root_stiffness_ratio[k] = c.root_stiffness_ratio;
  b.damping[k] = c.damping;
  b.static_friction[k] = c.static_friction;
}

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
    store_coefficients(b, k, c);
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
    store_coefficients(b, k, coefficients[pl.coefficient[static_cast<std::size_t>(k)]]);
  }
}
[[gnu::noinline, gnu::cold]] void set_offsets(PairLanes& pl, std::span<const Vec3> x_el, std::span<const Vec3> x_b,
                                              std::span<const Vec3> inverse_inertia,
                                              std::span<const std::uint32_t> owner,
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
    b.ji[k] = max_component(inverse_inertia[bi]), b.jj[k] = max_component(inverse_inertia[bj]);
  }
}

struct Workspace {
  PairLanes pairs;
  PartLanes parts;
};

// Everything the contact loop reads and writes, as plain views. The loop gets its own copy:
// a byte store (pair_active_) may alias any vector's internals or any shared variable, so
// through the vectors, or through variables shared by an OpenMP region, the compiler would
// reload every data pointer after it; from a private copy it keeps them in registers.
struct ContactViews {
  std::span<const Vec3> x_el, x_b, v_b, w_b, inertia, inverse_inertia;
  std::span<const double> radius, mass;
  std::span<const std::uint32_t> owner, sphere_count, species, first, second;
  std::span<const std::uint32_t> part_start, sphere_of_candidate, part_of_candidate, candidate_face_start,
      candidate_faces;
  std::span<const double> candidate_face_distance, element_moved2;
  double* history;
  double* part_history;
  std::span<std::uint8_t> candidate_touches;
  std::span<std::uint8_t> active;
  std::span<Vec3> pair_force, pair_torque_j, element_force, element_torque, part_reaction;
  std::span<double> pair_cdt_j, element_cdt;
  std::span<const std::uint8_t> second_direct;
  std::span<Vec3> second_force, second_torque;
  std::span<double> second_cdt;
  const PairCoefficients* coefficients;
  std::size_t n_species, n_types;
  std::span<const Part> parts;
  std::span<const PartCache> part_cache;
  int h;
  double dt;
  double damping_rate;  // largest tangential damping over the contact's sliding mass [1/s] (contact_batch.hpp)
};

struct ChunkResult {
  double max_ratio = 0.0;    // largest overlap over the smaller radius
  std::size_t touching = 0;  // sphere-sphere contacts
  double force_sum = 0.0;    // their force magnitudes, summed in pair order [N]
};

// The contacts of elements [e0, e1): their pairs [p0, p1) as first element, then their part
// candidates; each element's own sums are zeroed and rebuilt here.
template <class Rolling>
ChunkResult contact_chunk(const ContactViews& views, std::uint32_t e0, std::uint32_t e1, std::size_t p0, std::size_t p1,
                          Workspace& work) {
  const ContactViews own = views;
  const auto [x_el, x_b, v_b, w_b, inertia, inverse_inertia, radius, mass, owner, sphere_count, species, first, second,
              part_start, sphere_of_candidate, part_of_candidate, candidate_face_start, candidate_faces,
              candidate_face_distance, element_moved2, history, part_history, candidate_touches, active, pair_force,
              pair_torque_j, element_force, element_torque, part_reaction, pair_cdt_j, element_cdt, second_direct,
              second_force, second_torque, second_cdt, coefficient_data, n_species, n_types, parts, part_cache, h, dt,
              damping_rate] = own;
  auto coefficients = [&](std::size_t a, std::size_t b) -> const PairCoefficients& {
    return coefficient_data[a * n_species + b];
  };
  ChunkResult r;

  // --- sphere-sphere ---------------------------------------------------------------------
  // Solves the batch of pairs, updates their histories, applies rolling model R; side i adds
  // to its element's own sums (in pair order), side j's share to j's sum as second element
  // (or, where other threads have some of j's pairs, to the pair's slot).
  PairLanes& pl = work.pairs;
  PairBatch& pb = pl.batch;
  double deepest = 0.0, deepest_radius = 1.0;  // overlap and radius of the largest ratio [m]
  auto finish_pairs = [&] {
    solve(pb, dt, damping_rate);
    for (int k = 0; k < pb.size; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const std::uint32_t i = pl.element[kk], p = pl.pair[kk], j = second[p];
      double* hist = history + std::size_t{p} * static_cast<std::size_t>(h);
      hist[0] = pb.xi_x[k], hist[1] = pb.xi_y[k], hist[2] = pb.xi_z[k];
      Vec3 spring = Rolling::history_size ? load3(hist + 3) : Vec3{};
      double inertia_r = 0.0;
      if constexpr (std::is_same_v<Rolling, EpsdRolling>) {
        const std::uint32_t bi = owner[i], bj = owner[j];
        const double ii = min_moment(inertia[bi]) + mass[bi] * pb.arm_i[k] * pb.arm_i[k];
        const double ij = min_moment(inertia[bj]) + mass[bj] * pb.arm_j[k] * pb.arm_j[k];
        inertia_r = ii * ij / (ii + ij);
      }
      const RollingOutput roll = Rolling::torque({{pb.nx[k], pb.ny[k], pb.nz[k]},
                                                  {pb.wix[k], pb.wiy[k], pb.wiz[k]},
                                                  {pb.wjx[k], pb.wjy[k], pb.wjz[k]},
                                                  pb.arm_i[k],
                                                  pb.arm_j[k],
                                                  pb.r_star[k],
                                                  pb.normal_force[k],
                                                  pb.normal_stiffness[k],
                                                  coefficient_data[pl.coefficient[kk]].rolling_friction,
                                                  inertia_r,
                                                  dt},
                                                 spring);
      if constexpr (Rolling::history_size > 0) store3(hist + 3, spring);
      const Vec3 f{pb.fx[k], pb.fy[k], pb.fz[k]};
      Vec3 t_i{pb.tix[k], pb.tiy[k], pb.tiz[k]}, t_j{pb.tjx[k], pb.tjy[k], pb.tjz[k]};
      if constexpr (Rolling::has_torque) t_i += roll.torque_i, t_j += roll.torque_j;
      element_force[i] += f;
      r.force_sum += norm(f);
      element_torque[i] += t_i;
      element_cdt[i] += roll.cdt_i;
      if (second_direct[j]) {  // this thread has all of j's pairs as second: sum in pair order
        second_force[j] -= f;
        second_torque[j] += t_j;
        second_cdt[j] += roll.cdt_j;
      } else {  // the gather sums the slots in the same order
        pair_force[p] = f;
        pair_torque_j[p] = t_j;
        pair_cdt_j[p] = roll.cdt_j;
      }
      // The largest overlap over the smaller radius, compared by cross-multiplying.
      const double smaller = std::min(pb.ri[k], pb.rj[k]);
      if (pb.overlap[k] * deepest_radius > deepest * smaller) deepest = pb.overlap[k], deepest_radius = smaller;
    }
    r.touching += static_cast<std::size_t>(pb.size);
  };
  std::fill(element_force.begin() + e0, element_force.begin() + e1, Vec3{});
  std::fill(element_torque.begin() + e0, element_torque.begin() + e1, Vec3{});
  std::fill(element_cdt.begin() + e0, element_cdt.begin() + e1, 0.0);
  // Which pairs touch, without a branch on it: about a third of the pairs in the list do
  // not, in no predictable order. A contact that ended has its history zeroed (after the
  // loop, which stays free of calls).
  pl.touching.resize(p1 - p0);
  pl.ended.resize(p1 - p0);
  std::size_t n_touching = 0, n_ended = 0;
  {
    // Plain local pointers: the byte store to `active` may alias anything whose address
    // escaped (the views, the workspace's vectors), so through those the compiler reloaded
    // nine pointers from memory on every pair.
    const std::uint32_t *const first_of = first.data(), *const second_of = second.data();
    const double* const radius_of = radius.data();
    const std::uint32_t* const owner_of = owner.data();
    const Vec3* const x_of = x_el.data();
    std::uint32_t *const touching = pl.touching.data(), *const ended = pl.ended.data();
    std::uint8_t* const active_of = active.data();
    const double* const history_of = history;
    const auto stride = static_cast<std::size_t>(h);
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
      // loop's only scattered reads, its owner the batch fill's first (bench/README.md).
      if (constexpr std::size_t ahead_by = 16; p + ahead_by < p1) {
        const std::uint32_t ahead = second_of[p + ahead_by];
        __builtin_prefetch(x_of + ahead);
        __builtin_prefetch(radius_of + ahead);
        __builtin_prefetch(owner_of + ahead);
      }
    }
  }
  for (std::size_t e = 0; e < n_ended; ++e)
    std::fill_n(history + std::size_t{pl.ended[e]} * static_cast<std::size_t>(h), h, 0.0);
  // The touching pairs into batches, side i = the pair's first element. The coefficients
  // are stored once while every pair of the batch has the same (one material, the usual
  // case), the offsets not at all while every element is a lone sphere.
  for (std::size_t t0 = 0; t0 < n_touching; t0 += PairBatch::capacity) {
    const int n = static_cast<int>(std::min<std::size_t>(PairBatch::capacity, n_touching - t0));
    const auto ns = static_cast<std::uint32_t>(n_species);  // (a handful: the species table is square)
    const std::uint32_t co0 = species[first[pl.touching[t0]]] * ns + species[second[pl.touching[t0]]];
    bool lone = true, uniform = true;
    for (int k = 0; k < n; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const std::uint32_t p = pl.touching[t0 + kk];
      const std::uint32_t i = first[p], j = second[p], bi = owner[i], bj = owner[j];
      // (read in place: copies of the Vec3s went through the stack)
      const Vec3 &xi = x_el[i], &xj = x_el[j], &vi = v_b[bi], &vj = v_b[bj], &wi = w_b[bi], &wj = w_b[bj];
      pb.dx[k] = xj.x - xi.x, pb.dy[k] = xj.y - xi.y, pb.dz[k] = xj.z - xi.z;
      pb.ri[k] = radius[i], pb.rj[k] = radius[j];
      pb.vix[k] = vi.x, pb.viy[k] = vi.y, pb.viz[k] = vi.z;
      pb.vjx[k] = vj.x, pb.vjy[k] = vj.y, pb.vjz[k] = vj.z;
      pb.wix[k] = wi.x, pb.wiy[k] = wi.y, pb.wiz[k] = wi.z;
      pb.wjx[k] = wj.x, pb.wjy[k] = wj.y, pb.wjz[k] = wj.z;
      pb.mi[k] = mass[bi], pb.mj[k] = mass[bj];
      const double* hist = history + std::size_t{p} * static_cast<std::size_t>(h);
      pb.xi_x[k] = hist[0], pb.xi_y[k] = hist[1], pb.xi_z[k] = hist[2];
      // j's sums, which finish_pairs adds to after the batch is solved, miss the cache otherwise.
      __builtin_prefetch(&second_force[j], 1);
      __builtin_prefetch(&second_torque[j], 1);
      __builtin_prefetch(&second_cdt[j], 1);
      // And j's body position and inverse moments, which set_offsets reads for clumps.
      __builtin_prefetch(&x_b[bj]);
      __builtin_prefetch(&inverse_inertia[bj]);
      const std::uint32_t co = species[i] * ns + species[j];
      pl.coefficient[kk] = co;
      uniform &= co == co0;
      lone &= (sphere_count[bi] == 1) & (sphere_count[bj] == 1);
      pl.element[kk] = i;
      pl.pair[kk] = p;
    }
    pb.size = n;
    pb.centred = lone;
    pb.uniform = uniform;
    store_coefficients(pb, 0, coefficient_data[co0]);
    if (!uniform) set_coefficients(pl, coefficient_data);
    if (!lone) set_offsets(pl, x_el, x_b, inverse_inertia, owner, sphere_count, second);
    finish_pairs();
  }
  r.max_ratio = deepest / deepest_radius;

  // --- sphere-part -----------------------------------------------------------------------
  PartLanes& lanes = work.parts;
  // A part candidate's contacts (up to max_part_touches) go into the batch with side i = the
  // sphere. Each takes the history slot whose stored normal is closest to its own, so that
  // a contact sliding across the triangles of one part keeps its history. Returns the
  // largest overlap ratio, or -1 if nothing touches.
  const std::size_t slot_size = 3 + static_cast<std::size_t>(h);
  auto visit_part = [&](std::size_t cw) -> double {
    const std::uint32_t s = sphere_of_candidate[cw], w = part_of_candidate[cw];
    const std::uint32_t b = owner[s];
    const PartCache& pc = part_cache[w];
    const Part& part = parts[w];
    const Vec3 origin = part.pose.position;
    std::array<PartTouch, max_part_touches> touches;
    const std::size_t f0 = candidate_face_start[cw], nf = candidate_face_start[cw + 1] - f0;
    // Faces further than the sphere and the part have moved since the build are skipped.
    const int n = part_touches(
        pc.faces, candidate_faces.subspan(f0, nf), transpose_times(pc.rotation, x_el[s] - origin), radius[s], touches,
        candidate_face_distance.subspan(f0, nf), nf > 1 ? std::sqrt(element_moved2[s]) + pc.moved : 0.0);
    double* slots = part_history + cw * max_part_touches * slot_size;
    part_reaction[2 * cw] = part_reaction[2 * cw + 1] = Vec3{};
    candidate_touches[cw] = static_cast<std::uint8_t>(n);
    std::array<bool, max_part_touches> used{};
    double max_ratio = -1.0;
    for (int k = 0; k < n; ++k) {
      const PartTouch& t = touches[static_cast<std::size_t>(k)];
      const Vec3 normal = pc.rotation * t.normal, point = origin + pc.rotation * t.point;
      // The slot: closest stored normal within 60 degrees, else a free one, else any unused.
      int slot = -1;
      double best = 0.5;
      for (int j = 0; j < max_part_touches; ++j) {
        const double c = dot(load3(slots + j * slot_size), normal);
        if (!used[static_cast<std::size_t>(j)] && c > best) best = c, slot = j;
      }
      for (int j = 0; j < max_part_touches && slot < 0; ++j) {
        if (!used[static_cast<std::size_t>(j)] && norm2(load3(slots + j * slot_size)) == 0.0) slot = j;
      }
      for (int j = 0; j < max_part_touches && slot < 0; ++j) {
        if (!used[static_cast<std::size_t>(j)]) slot = j, std::fill_n(slots + j * slot_size, slot_size, 0.0);
      }
      used[static_cast<std::size_t>(slot)] = true;
      double* hist = slots + static_cast<std::size_t>(slot) * slot_size;
      store3(hist, normal);
      const Vec3 arm = point - x_b[b];
      const Vec3 v_part = part.twist.velocity + cross(part.twist.angular_velocity, point - origin);
      const Vec3 v_rel = v_b[b] + cross(w_b[b], arm) - v_part;
      const double arm_len = norm(arm);
      const PairCoefficients& co = coefficients(species[s], n_types + w);
      LaneExtra& e = lanes.next();
      e.element = s;
      e.item = static_cast<std::uint32_t>(cw);
      e.history = hist + 3;
      e.arm_i = arm;
      e.arm_j = point - origin;  // for the reaction's torque about the part origin
      if constexpr (Rolling::uses_spin) {
        e.omega_i = w_b[b];
        e.omega_j = part.twist.angular_velocity;
      }
      e.arm_i_len = arm_len;
      e.inertia_r = min_moment(inertia[b]) + mass[b] * arm_len * arm_len;
      e.mu_r = co.rolling_friction;
      lanes.push(normal, t.overlap, v_rel, radius[s], mass[b],
                 1.0 / mass[b] + arm_len * arm_len * max_component(inverse_inertia[b]), co);
      max_ratio = std::max(max_ratio, t.overlap / radius[s]);
    }
    for (int j = 0; j < max_part_touches; ++j) {  // contacts that ended start afresh
      double* slot = slots + j * slot_size;       // (a slot in use has a non-zero normal)
      if (!used[static_cast<std::size_t>(j)] && norm2(load3(slot)) != 0.0) std::fill_n(slot, slot_size, 0.0);
    }
    return max_ratio;
  };
  // Solves the batch, updates the histories, applies rolling model R; the sphere adds to its
  // element's own sums (after its pairs), the part candidate's reaction takes the rest (a
  // candidate may have several contacts).
  auto finish_parts = [&] {
    ContactBatch& b = lanes.batch;
    solve(b, dt, damping_rate);
    for (int k = 0; k < b.size; ++k) {
      const LaneExtra& e = lanes.extra[static_cast<std::size_t>(k)];
      e.history[0] = b.xi_x[k], e.history[1] = b.xi_y[k], e.history[2] = b.xi_z[k];
      Vec3 spring = Rolling::history_size ? load3(e.history + 3) : Vec3{};
      const RollingOutput roll = Rolling::torque({{b.nx[k], b.ny[k], b.nz[k]},
                                                  e.omega_i,
                                                  e.omega_j,
                                                  e.arm_i_len,
                                                  0.0,
                                                  b.r_star[k],
                                                  b.normal_force[k],
                                                  b.normal_stiffness[k],
                                                  e.mu_r,
                                                  e.inertia_r,
                                                  dt},
                                                 spring);
      if constexpr (Rolling::history_size > 0) store3(e.history + 3, spring);
      const Vec3 f{b.fx[k], b.fy[k], b.fz[k]};
      element_force[e.element] += f;
      element_torque[e.element] += cross(e.arm_i, f) + roll.torque_i;
      element_cdt[e.element] += roll.cdt_i;
      part_reaction[2 * std::size_t{e.item}] -= f;
      part_reaction[2 * std::size_t{e.item} + 1] += cross(e.arm_j, -f) - roll.torque_i;
    }
    b.size = 0;
  };
  for (std::size_t cw = part_start[e0]; cw < part_start[e1]; ++cw) {
    if (lanes.batch.size + max_part_touches > ContactBatch::capacity) finish_parts();
    r.max_ratio = std::max(r.max_ratio, visit_part(cw));
  }
  finish_parts();
  return r;
}

}  // namespace

namespace {}  // namespace

Simulation::Simulation(SimulationSettings settings)
    : settings_(std::move(settings)), rolling_(rolling_model(settings_.rolling)), neighbors_(1.0, 3) {
  set_time_step(settings_.dt);  // (its check)
  if (settings_.skin < 0.0) throw InputError("expected a non-negative skin").with_key("skin");
  if (!(settings_.tangential_damping_limit > 0.0)) {
    throw InputError("expected a positive fraction, or infinity for none").with_key("tangential_damping_limit");
  }
}

void Simulation::set_time_step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw InputError("expected a positive time step").with_key("dt");
  settings_.dt = dt;
}

std::size_t Simulation::add_part(Part part) {
  const std::string key = "parts." + part.name;
  if (part.name.empty()) throw InputError("expected a name for every geometry part").with_key("parts");
  for (const Part& other : parts_) {
    if (other.name == part.name) throw InputError("two geometry parts are called '" + part.name + "'").with_key(key);
  }
  try {
    validate(part.material);
    validate_motion(part.shape, part.motion);
    const Quat& q = part.pose.orientation;
    if (!std::isfinite(norm(part.pose.position)) || !std::isfinite(norm2(q)) || norm2(q) < 1e-12) {
      throw InputError("expected a finite position in m and a non-zero finite orientation quaternion").with_key("pose");
    }
    PartCache cache;
    cache.faces = faces_of(part.shape);
    const bool plane = std::holds_alternative<PlaneSpec>(part.shape);
    cache.lo = Vec3{INFINITY, INFINITY, INFINITY};
    cache.hi = -1.0 * cache.lo;
    for (const Face& f : cache.faces) {
      Vec3 lo, hi;
      bounds(f, lo, hi);
      cache.lo = min(cache.lo, lo);
      cache.hi = max(cache.hi, hi);
    }
    const Vec3 far = max(-1.0 * cache.lo, cache.hi);
    cache.reach = plane ? std::numeric_limits<double>::infinity() : norm(far);
    // A grid pays off once a sphere would otherwise test many faces.
    cache.use_grid = cache.faces.size() > 16;
    if (cache.use_grid) cache.grid = FaceGrid(cache.faces);
    part.pose.orientation = normalized(part.pose.orientation);
    cache.rotation = to_matrix(part.pose.orientation);
    part.twist = twist_at(part.motion, 0.0, part.pose, time_);
    part_cache_.push_back(std::move(cache));
  } catch (const InputError& e) {
    throw e.with_key(key);
  }
  parts_.push_back(std::move(part));
  parts_changed_ = true;
  return parts_.size() - 1;
}

std::size_t Simulation::part_index(const std::string& name) const {
  std::string names;
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    if (parts_[i].name == name) return i;
    names += (i ? ", " : "") + parts_[i].name;
  }
  throw InputError("no geometry part called '" + name + "' (parts: " + names + ")").with_key("parts");
}

void Simulation::set_motion(std::size_t i, Motion motion) {
  try {
    validate_motion(parts_.at(i).shape, motion);
  } catch (const InputError& e) {
    throw e.with_key("parts." + parts_.at(i).name);
  }
  parts_.at(i).motion = std::move(motion);
  parts_[i].servo = {};
  parts_[i].twist = twist_at(parts_[i].motion, 0.0, parts_[i].pose, time_);
}

TriangleMesh Simulation::part_surface(std::size_t i, int segments, double plane_half_size) const {
  TriangleMesh m = tessellate(part_cache_.at(i).faces, segments, plane_half_size);
  for (Vec3& v : m.vertices) v = parts_[i].pose.position + part_cache_[i].rotation * v;
  return m;
}

void Simulation::prepare() {
  const auto& types = particles_.types();
  if (types.size() != prepared_types_ || parts_.size() != prepared_parts_) {
    std::vector<Species> species;
    std::vector<const Material*> materials;
    for (const auto& t : types) {
      species.push_back({t.name, t.material.name});
      materials.push_back(&t.material);
    }
    for (const auto& w : parts_) {
      species.push_back({w.name, w.material.name});
      materials.push_back(&w.material);
    }
    const DenseContactTable dense = settings_.contacts.resolve(species);
    const std::size_t n = species.size();
    std::vector<PairCoefficients> c(n * n);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j)
        c[i * n + j] = make_pair_coefficients(*materials[i], *materials[j], dense(i, j));
    }
    coefficients_ = PairCoefficientTable(n, std::move(c));
    if (!neighbors_configured_ && !types.empty()) {
      // The adaptive skin starts at 0.11 of the largest element diameter (0.40 mm for 3.64 mm
      // spheres): on the pour benchmark it ran the settled bed 13% faster than 0.25 d and the
      // pour as fast (bench/README.md); rebuild() widens it up to 0.35 d where the particles
      // move fast. The cell size of later builds follows the largest element present, so
      // adding bigger types stays correct.
      double r_max = 0.0;
      for (const auto& t : types) {
        for (const auto& e : t.shape.spheres) r_max = std::max(r_max, e.radius);
      }
      skin_min_ = settings_.skin > 0.0 ? settings_.skin : skin_least_per_radius * r_max;
      skin_max_ = settings_.skin > 0.0 ? settings_.skin : skin_most_per_radius * r_max;
      neighbors_ = NeighborList(skin_min_, history_size(rolling_));
      neighbors_configured_ = true;
    }
    prepared_types_ = types.size();
    prepared_parts_ = parts_.size();
  }
  const std::size_t n_s = particles_.spheres();
  // New particles or parts: the last forces (velocity Verlet's first half kick) are stale.
  if (element_force_.size() != n_s || parts_.size() != forces_parts_) forces_valid_ = false;
  forces_parts_ = parts_.size();
  element_force_.resize(n_s);
  element_torque_.resize(n_s);
  element_cdt_.resize(n_s);
  second_force_.resize(n_s);
  second_torque_.resize(n_s);
  second_cdt_.resize(n_s);
  second_direct_.resize(n_s);
  element_moved2_.resize(n_s, 0.0);  // a build is due for new elements anyway (size change)
  particles_.update_sphere_positions();
}

void Simulation::set_part_enabled(std::size_t i, bool enabled) {
  if (i >= parts_.size()) throw std::out_of_range("Simulation::set_part_enabled: no such part");
  if (parts_[i].enabled == enabled) return;
  parts_[i].enabled = enabled;
  parts_changed_ = true;  // the candidates are found again before the next contacts
}

// The members save_state writes after the particles and the neighbour list, in file order:
// one list for writing and reading (Self is Simulation or const Simulation).
template <class Self, class F>
void Simulation::each_saved_member(Self& self, F&& f) {
  static_assert(std::is_same_v<std::size_t, std::uint64_t>, "counts are stored as 64-bit");
  f(self.pair_force_);
  f(self.pair_torque_j_);
  f(self.pair_cdt_j_);
  f(self.pair_active_);
  f(self.element_force_);
  f(self.element_torque_);
  f(self.element_cdt_);
  f(self.second_force_);
  f(self.second_torque_);
  f(self.second_cdt_);
  f(self.second_direct_);
  f(self.chunk_start_);
  f(self.part_start_);
  f(self.part_of_candidate_);
  f(self.sphere_of_candidate_);
  f(self.candidate_sphere_id_);
  f(self.candidate_face_start_);
  f(self.candidate_faces_);
  f(self.candidate_face_distance_);
  f(self.element_moved2_);
  f(self.part_history_);
  f(self.part_reaction_);
  f(self.candidate_touches_);
  f(self.part_partial_);
  f(self.forces_valid_);
  f(self.rebuild_due_);
  f(self.parts_changed_);
  f(self.direct_team_);
  f(self.time_);
  f(self.steps_);
  f(self.max_overlap_ratio_);
  f(self.forces_parts_);
  f(self.active_build_);
  f(self.direct_build_);
  f(self.contacts_);
}

void Simulation::save_state(io::BinaryWriter& out) const {
  out.put(static_cast<std::uint64_t>(parts_.size()));
  for (std::size_t w = 0; w < parts_.size(); ++w) {
    const Part& p = parts_[w];
    out.put(p.pose);
    out.put(p.enabled);
    out.put(p.motion.segments);
    out.put(p.motion.has_servo);
    out.put(p.motion.servo);
    out.put(p.force);
    out.put(p.torque);
    out.put(p.twist);
    out.put(p.servo);
    out.put(static_cast<std::uint64_t>(p.touches));
    out.put(part_cache_[w].moved);
  }
  particles_.save(out);
  neighbors_.save(out);
  each_saved_member(*this, [&](const auto& m) { out.put(m); });
}

void Simulation::load_state(io::BinaryReader& in) {
  if (in.get<std::uint64_t>() != parts_.size()) {
    throw InputError("the checkpoint has another number of geometry parts than the scenario");
  }
  for (std::size_t w = 0; w < parts_.size(); ++w) {
    Part& p = parts_[w];
    in.get(p.pose);
    in.get(p.enabled);
    in.get(p.motion.segments);
    in.get(p.motion.has_servo);
    in.get(p.motion.servo);
    in.get(p.force);
    in.get(p.torque);
    in.get(p.twist);
    in.get(p.servo);
    p.touches = static_cast<std::size_t>(in.get<std::uint64_t>());
    in.get(part_cache_[w].moved);
    part_cache_[w].rotation = to_matrix(p.pose.orientation);
  }
  particles_.load(in);
  // The derived tables (pair coefficients) and the neighbour list's configuration, then the
  // saved list and every per-pair and per-element array over them.
  const std::vector<Vec3> placed = particles_.sphere_position;
  prepare();
  particles_.sphere_position = placed;
  neighbors_.load(in);
  each_saved_member(*this, [&](auto& m) { in.get(m); });
  last_build_step_ = steps_;  // (load_skin_clock reads the saved one, where there is one)
}

void Simulation::remove_bodies(std::span<const std::size_t> bodies) {
  if (bodies.empty()) return;
  const std::size_t n = particles_.bodies();
  std::vector<std::uint8_t> gone(n, 0);
  for (const std::size_t b : bodies) {
    if (b >= n || gone[b]) throw std::out_of_range("Simulation::remove_bodies: bad or repeated body index");
    gone[b] = 1;
  }
  std::vector<std::uint32_t> keep;
  keep.reserve(n - bodies.size());
  for (std::size_t b = 0; b < n; ++b) {
    if (!gone[b]) keep.push_back(static_cast<std::uint32_t>(b));
  }
  particles_.permute(keep);  // a permutation onto a subset drops the rest
  // The neighbour list and the part candidates index elements: both are found again now
  // (their histories follow the stable ids), so that what reads them between steps (a
  // sensor) sees the bodies that remain; the stored forces belong to the old bodies.
  prepare();
  rebuild();
  rebuild_due_ = -1;
  forces_valid_ = false;
}

void Simulation::spatial_sort() {
  auto& ps = particles_;
  const std::size_t n = ps.bodies();
  if (n < 2) return;
  Vec3 lo{INFINITY, INFINITY, INFINITY};
  for (const auto& p : ps.position) lo = min(lo, p);
  double r_max = 0.0;
  for (const double r : ps.radius) r_max = std::max(r_max, r);
  const double cell = 2.0 * r_max + neighbors_.skin();
  // Cells of a cube of side 1024 cells, z-major: neighbours in space become neighbours in memory.
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

void Simulation::rebuild(bool adapt_skin) {
  // The adaptive skin trades the list's length (every pair in it is tested every step)
  // against how often it is rebuilt (a build costs a few steps). Where the fastest element
  // crossed half the skin in fewer than 40 steps (a stream falling from a funnel) the skin
  // grows, up to 0.35 d; where it took more than 160 it shrinks, down to 0.11 d (a settled
  // bed). On the reduced calibration cup this ran single spheres 9 % faster than 0.11 d
  // fixed, and clumps as fast (docs/engine.md). It depends only on step counts, so every
  // thread count follows the same skins.
  if (adapt_skin && skin_max_ > skin_min_) {
    const std::uint64_t interval = steps_ - last_build_step_;
    if (interval < skin_widen_below_steps) neighbors_.set_skin(std::min(skin_max_, skin_factor * neighbors_.skin()));
    if (interval > skin_narrow_above_steps) neighbors_.set_skin(std::max(skin_min_, neighbors_.skin() / skin_factor));
  }
  last_build_step_ = steps_;
  if (settings_.sort_every > 0 && neighbors_.builds() % static_cast<std::size_t>(settings_.sort_every) == 0) {
    spatial_sort();
  }
  const auto& ps = particles_;
  neighbors_.build(ps.sphere_position, ps.radius, ps.owner, ps.sphere_id);
  find_part_candidates();
  split_into_chunks();
}

void Simulation::find_part_candidates() {
  // No element moves more than half the skin between builds, and a build is due when a part
  // has moved half the skin (move_parts), so a sphere further than the skin from a face
  // cannot reach it before the next build.
  const auto& ps = particles_;
  const std::size_t n_s = ps.spheres(), n_w = parts_.size();
  const std::size_t slots = max_part_touches * (3 + static_cast<std::size_t>(neighbors_.history_size()));
  const double skin = neighbors_.skin();
  // Histories of the last build, found again by (sphere id, part).
  std::vector<std::uint32_t> old_first(
      ps.sphere_id.empty() ? 0 : *std::max_element(ps.sphere_id.begin(), ps.sphere_id.end()) + 1, UINT32_MAX);
  for (std::size_t c = candidate_sphere_id_.size(); c-- > 0;) {
    if (candidate_sphere_id_[c] < old_first.size()) old_first[candidate_sphere_id_[c]] = static_cast<std::uint32_t>(c);
  }
  const std::vector<std::uint32_t> old_part = std::move(part_of_candidate_), old_id = std::move(candidate_sphere_id_);
  const std::vector<double> old_history = std::move(part_history_);
  part_start_.assign(n_s + 1, 0);
  part_of_candidate_.clear();
  sphere_of_candidate_.clear();
  candidate_sphere_id_.clear();
  candidate_face_start_.assign(1, 0);
  candidate_faces_.clear();
  candidate_face_distance_.clear();
  element_moved2_.assign(n_s, 0.0);
  part_history_.clear();
  std::vector<std::uint32_t> near;
  for (std::size_t s = 0; s < n_s; ++s) {
    const double reach = ps.radius[s] + skin;
    for (std::size_t w = 0; w < n_w; ++w) {
      if (!parts_[w].enabled) continue;
      const PartCache& pc = part_cache_[w];
      const Vec3 p = transpose_times(pc.rotation, ps.sphere_position[s] - parts_[w].pose.position);
      if (p.x < pc.lo.x - reach || p.y < pc.lo.y - reach || p.z < pc.lo.z - reach || p.x > pc.hi.x + reach ||
          p.y > pc.hi.y + reach || p.z > pc.hi.z + reach) {
        continue;
      }
      near.clear();
      if (pc.use_grid) {
        pc.grid.query(p, reach, near);
      } else {
        for (std::size_t f = 0; f < pc.faces.size(); ++f) near.push_back(static_cast<std::uint32_t>(f));
      }
      const std::size_t first_face = candidate_faces_.size();
      for (const std::uint32_t f : near) {
        const double d = nearest(pc.faces[f], p).distance;
        if (d < reach) candidate_faces_.push_back(f), candidate_face_distance_.push_back(d);
      }
      if (candidate_faces_.size() == first_face) continue;
      candidate_face_start_.push_back(static_cast<std::uint32_t>(candidate_faces_.size()));
      part_of_candidate_.push_back(static_cast<std::uint32_t>(w));
      sphere_of_candidate_.push_back(static_cast<std::uint32_t>(s));
      candidate_sphere_id_.push_back(ps.sphere_id[s]);
      const std::size_t at = part_history_.size();
      part_history_.resize(at + slots, 0.0);
      const std::uint32_t id = ps.sphere_id[s];
      for (std::size_t c = id < old_first.size() ? old_first[id] : UINT32_MAX; c < old_id.size() && old_id[c] == id;
           ++c) {
        if (old_part[c] == w) std::copy_n(old_history.data() + c * slots, slots, part_history_.data() + at);
      }
    }
    part_start_[s + 1] = static_cast<std::uint32_t>(part_of_candidate_.size());
  }
  part_reaction_.assign(2 * part_of_candidate_.size(), Vec3{});
  candidate_touches_.assign(part_of_candidate_.size(), 0);
  for (PartCache& pc : part_cache_) pc.moved = 0.0;
  parts_changed_ = false;
}

namespace {
// The chunks [first, last) that thread `me` of a team of `team` handles: contiguous blocks
// of nearly equal size, in order.
std::pair<std::size_t, std::size_t> chunks_of(std::size_t n_chunks, int team, int me) {
  const auto t = static_cast<std::size_t>(team), m = static_cast<std::size_t>(me);
  return {n_chunks * m / t, n_chunks * (m + 1) / t};
}
}  // namespace

void Simulation::mark_direct_seconds(int team) {
  // An element's shares as second element may be summed by the contact loop itself when one
  // thread computes all its pairs as second: that thread meets them in pair order.
  const std::size_t n_s = particles_.spheres(), n_chunks = chunk_start_.size() - 1;
  std::vector<int> thread_of(n_s, 0);
  for (int t = 0; t < team; ++t) {
    const auto [c0, c1] = chunks_of(n_chunks, team, t);
    std::fill(thread_of.begin() + chunk_start_[c0], thread_of.begin() + chunk_start_[c1], t);
  }
  const auto first = neighbors_.firsts();
  std::fill(second_direct_.begin(), second_direct_.end(), 1);  // (sized by prepare: views hold it)
  for (std::size_t s = 0; s < n_s; ++s) {
    const auto pairs = neighbors_.pairs_as_second(s);
    for (const std::uint32_t p : pairs) {
      if (thread_of[first[p]] != thread_of[first[pairs.front()]]) second_direct_[s] = 0;
    }
  }
  direct_build_ = neighbors_.builds();
  direct_team_ = team;
}

void Simulation::split_into_chunks() {
  // Runs of whole elements with about 256 pairs and part candidates each (with pair batches
  // of 64, 3% faster than runs of 128; 512 was no faster): a fixed split (the thread count
  // plays no part), and each element's own sums stay in one chunk.
  constexpr std::size_t chunk_load = 256;
  const std::size_t n_s = particles_.spheres();
  chunk_start_.assign(1, 0);
  std::size_t load = 0;
  for (std::size_t s = 0; s < n_s; ++s) {
    load += neighbors_.begin_of(s + 1) - neighbors_.begin_of(s) + part_start_[s + 1] - part_start_[s];
    if (load >= chunk_load || s + 1 == n_s) {
      chunk_start_.push_back(static_cast<std::uint32_t>(s + 1));
      load = 0;
    }
  }
}

template <class Rolling>
void Simulation::compute_forces(const Rolling&) {
  auto& ps = particles_;
  const double dt = settings_.dt;
  const std::size_t n_pairs = neighbors_.pairs();
  pair_force_.resize(n_pairs);
  pair_torque_j_.resize(n_pairs);
  pair_cdt_j_.resize(n_pairs);
  if (neighbors_.builds() != active_build_) {
    // A new list: every pair counts as touching once, so that where it does not, its history
    // is zeroed; from then on only pairs whose contact ends write zeros.
    pair_active_.assign(n_pairs, 1);
    active_build_ = neighbors_.builds();
  }
  const ContactViews views{ps.sphere_position,
                           ps.position,
                           ps.velocity,
                           ps.angular_velocity,
                           ps.inertia,
                           ps.inverse_inertia,
                           ps.radius,
                           ps.mass,
                           ps.owner,
                           ps.sphere_count,
                           ps.species,
                           neighbors_.firsts(),
                           neighbors_.seconds(),
                           part_start_,
                           sphere_of_candidate_,
                           part_of_candidate_,
                           candidate_face_start_,
                           candidate_faces_,
                           candidate_face_distance_,
                           element_moved2_,
                           neighbors_.all_history().data(),
                           part_history_.data(),
                           candidate_touches_,
                           pair_active_,
                           pair_force_,
                           pair_torque_j_,
                           element_force_,
                           element_torque_,
                           part_reaction_,
                           pair_cdt_j_,
                           element_cdt_,
                           second_direct_,
                           second_force_,
                           second_torque_,
                           second_cdt_,
                           coefficients_.size() > 0 ? &coefficients_(0, 0) : nullptr,
                           coefficients_.size(),
                           ps.types().size(),
                           parts_,
                           part_cache_,
                           neighbors_.history_size(),
                           dt,
                           settings_.tangential_damping_limit / dt};

  // --- contacts, per chunk of elements: their pairs (as first element), then their parts ---
  double max_ratio = 0.0;
  std::size_t touching = 0;
  const std::size_t n_chunks = chunk_start_.size() - 1;
  chunk_force_sum_.resize(n_chunks);
#pragma omp parallel reduction(max : max_ratio) reduction(+ : touching) if (static_cast <std::ptrdiff_t>(ps.spheres()) > \
                                                                                parallel_threshold)
  {
    int team = 1, me = 0;
#ifdef BUSHEL_HAVE_OPENMP
    team = omp_get_num_threads(), me = omp_get_thread_num();
#endif
    // Each thread takes a fixed block of chunks (chunks_of), which mark_direct_seconds knows.
#pragma omp single
    if (direct_build_ != neighbors_.builds() || direct_team_ != team) mark_direct_seconds(team);
    // Each thread's scratch, kept between steps: allocating and zeroing it every step cost
    // more than the L1 cache holds.
    thread_local std::unique_ptr<Workspace> work;
    if (!work) work = std::make_unique<Workspace>();
    const auto [c0, c1] = chunks_of(n_chunks, team, me);
    for (std::size_t c = c0; c < c1; ++c) {
      const std::uint32_t e0 = chunk_start_[c], e1 = chunk_start_[c + 1];
      const ChunkResult r =
          contact_chunk<Rolling>(views, e0, e1, neighbors_.begin_of(e0), neighbors_.begin_of(e1), *work);
      max_ratio = std::max(max_ratio, r.max_ratio);
      touching += r.touching;
      chunk_force_sum_[c] = r.force_sum;
    }
  }
  // (summed in chunk order: the same sum for any thread count)
  pair_force_sum_ = 0.0;
  for (std::size_t c = 0; c < n_chunks; ++c) pair_force_sum_ += chunk_force_sum_[c];
  sum_part_reactions();

  // --- gather onto bodies, in a fixed order -------------------------------------------------
  // Per element: its own sums, then the sum of its shares as second element in pair order,
  // which the contact loop kept (direct) or which is summed here from the pair slots in the
  // same order; the accumulators are zeroed for the next step.
  const auto nb = static_cast<std::ptrdiff_t>(ps.bodies());
  const Vec3 g = settings_.gravity;
#pragma omp parallel for schedule(static) if (nb > parallel_threshold)
  for (std::ptrdiff_t sb = 0; sb < nb; ++sb) {
    const auto b = static_cast<std::size_t>(sb);
    Vec3 f = ps.mass[b] * g, t;
    double cdt = 0.0;
    for (std::uint32_t s = ps.first_sphere[b]; s < ps.first_sphere[b] + ps.sphere_count[b]; ++s) {
      f += element_force_[s];
      t += element_torque_[s];
      cdt += element_cdt_[s];
      if (second_direct_[s]) {
        f += second_force_[s];
        t += second_torque_[s];
        cdt += second_cdt_[s];
        second_force_[s] = second_torque_[s] = Vec3{};
        second_cdt_[s] = 0.0;
        continue;
      }
      Vec3 f_second, t_second;
      double cdt_second = 0.0;
      for (const std::uint32_t p : neighbors_.pairs_as_second(s)) {
        if (!pair_active_[p]) continue;  // (as the contact loop: only pairs that touch)
        f_second -= pair_force_[p];
        t_second += pair_torque_j_[p];
        cdt_second += pair_cdt_j_[p];
      }
      f += f_second;
      t += t_second;
      cdt += cdt_second;
    }
    ps.force[b] = f;
    ps.torque[b] = t;
    ps.rolling_resistance[b] = cdt;
  }
  max_overlap_ratio_ = max_ratio;
  peak_overlap_ratio_ = std::max(peak_overlap_ratio_, max_ratio);
  contacts_ = touching;
  forces_valid_ = true;
}

void Simulation::sum_part_reactions() {
  // Fixed chunks of candidates, summed in order: the same sums for any thread count, without
  // a serial pass over every candidate.
  const std::size_t n_w = parts_.size(), n_c = part_of_candidate_.size();
  part_force_sum_ = 0.0;
  part_contacts_ = 0;
  if (n_w == 0) return;
  constexpr std::size_t chunks = 64;
  const std::size_t per_chunk = (n_c + chunks - 1) / chunks;
  part_partial_.assign(3 * chunks * n_w, Vec3{});  // force, torque, (touches, sum of |force|, touching)
  const auto nc = static_cast<std::ptrdiff_t>(chunks);
#pragma omp parallel for schedule(static) if (static_cast <std::ptrdiff_t>(n_c) > parallel_threshold)
  for (std::ptrdiff_t sc = 0; sc < nc; ++sc) {
    const auto k = static_cast<std::size_t>(sc);
    Vec3* out = part_partial_.data() + 3 * k * n_w;
    for (std::size_t c = k * per_chunk; c < std::min(n_c, (k + 1) * per_chunk); ++c) {
      const std::uint32_t w = part_of_candidate_[c];
      out[3 * w] += part_reaction_[2 * c];
      out[3 * w + 1] += part_reaction_[2 * c + 1];
      out[3 * w + 2].x += candidate_touches_[c];
      out[3 * w + 2].y += norm(part_reaction_[2 * c]);
      out[3 * w + 2].z += candidate_touches_[c] > 0 ? 1.0 : 0.0;
    }
  }
  for (std::size_t w = 0; w < n_w; ++w) {
    Vec3 f, t;
    double touches = 0.0;
    for (std::size_t k = 0; k < chunks; ++k) {
      f += part_partial_[3 * (k * n_w + w)];
      t += part_partial_[3 * (k * n_w + w) + 1];
      touches += part_partial_[3 * (k * n_w + w) + 2].x;
      part_force_sum_ += part_partial_[3 * (k * n_w + w) + 2].y;
      part_contacts_ += static_cast<std::size_t>(part_partial_[3 * (k * n_w + w) + 2].z);
    }
    parts_[w].force = f;
    parts_[w].torque = t;
    parts_[w].touches = static_cast<std::size_t>(touches);
  }
}

void Simulation::save_force_sums(io::BinaryWriter& out) const {
  out.put(pair_force_sum_);
  out.put(part_force_sum_);
  out.put(static_cast<std::uint64_t>(part_contacts_));
}

void Simulation::save_skin_clock(io::BinaryWriter& out) const { out.put(last_build_step_); }

void Simulation::load_skin_clock(io::BinaryReader& in) { in.get(last_build_step_); }

void Simulation::load_force_sums(io::BinaryReader& in) {
  in.get(pair_force_sum_);
  in.get(part_force_sum_);
  part_contacts_ = static_cast<std::size_t>(in.get<std::uint64_t>());
}

double Simulation::unbalanced_force_ratio() const {
  const auto& ps = particles_;
  const std::size_t n = ps.bodies(), touching = contacts_ + part_contacts_;
  if (n == 0) return 0.0;
  double net = 0.0;  // (in body order: the same sum for any thread count)
  for (std::size_t b = 0; b < n; ++b) net += norm(ps.force[b]);
  const double contact = pair_force_sum_ + part_force_sum_;
  if (touching == 0 || !(contact > 0.0)) return net > 0.0 ? 1.0 : 0.0;
  return (net / static_cast<double>(n)) / (contact / static_cast<double>(touching));
}

void Simulation::move_parts(double t, double dt) {
  for (std::size_t w = 0; w < parts_.size(); ++w) {
    Part& part = parts_[w];
    if (part.motion.empty()) continue;
    PartCache& pc = part_cache_[w];
    pc.moved += advance(part.motion, part.servo.speed, part.pose, t, dt, pc.reach);
    pc.rotation = to_matrix(part.pose.orientation);
    part.twist = twist_at(part.motion, part.servo.speed, part.pose, t + dt);
    // A face may now be up to `moved` closer to a sphere than at the last build.
    if (pc.moved > 0.5 * neighbors_.skin()) parts_changed_ = true;
  }
}

void Simulation::update_servos() {
  for (Part& part : parts_) {
    if (part.motion.has_servo)
      part.servo = update_servo(part.motion.servo, part.servo, part.force, part.pose.position, time_);
  }
}

void Simulation::compute_forces() {
  // The last drift measured each element's displacement since the build (for the rebuild
  // test and the part-face bound); after changes from outside (-1) this pass measures them.
  // An element added since the build has an infinite displacement, so it forces a build.
  bool due = rebuild_due_ > 0, moved = due;
  if (rebuild_due_ < 0) {
    const auto& x = particles_.sphere_position;
    const auto n = static_cast<std::ptrdiff_t>(x.size());
    double worst = 0.0;
#pragma omp parallel for schedule(static) reduction(max : worst) if (n > parallel_threshold)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const auto e = static_cast<std::size_t>(i);
      element_moved2_[e] = neighbors_.displacement2(e, x[e]);
      worst = std::max(worst, element_moved2_[e]);
    }
    due = neighbors_.needs_rebuild(worst);
    // (not motion: the first build, or elements added since the last)
    moved = due && std::isfinite(worst) && neighbors_.builds() > 0;
  }
  // A skin wider than the least is narrowed once 160 steps pass without a build, rather than
  // at the next build that motion causes, which is rare once the particles rest: a bed that
  // settles after a flow soon runs at the narrowest skin again.
  const bool narrow = neighbors_.skin() > skin_min_ && steps_ - last_build_step_ > skin_narrow_above_steps;
  if (parts_changed_ || due || narrow) rebuild(moved || narrow);
  std::visit([this](const auto& model) { compute_forces(model); }, rolling_);
}

void Simulation::kick(double dt) {
  auto& ps = particles_;
  const auto nb = static_cast<std::ptrdiff_t>(ps.bodies());
#pragma omp parallel for schedule(static) if (nb > parallel_threshold)
  for (std::ptrdiff_t sb = 0; sb < nb; ++sb) {
    const auto b = static_cast<std::size_t>(sb);
    ps.velocity[b] += ps.force[b] * (dt / ps.mass[b]);
    const Vec3& inv_inertia = ps.inverse_inertia[b];
    const Vec3 omega = ps.angular_velocity[b];
    const double w0 = norm(omega);
    const bool resisted = ps.rolling_resistance[b] > 0.0 && w0 > 0.0;
    if (is_isotropic(ps.inertia[b])) {  // same cap as below, in omega instead of L
      Vec3 w = omega + ps.torque[b] * (dt * inv_inertia.x);
      if (resisted) {
        const Vec3 u = omega / w0;
        const double along = dot(w, u);
        if (along > 0.0) w -= std::min(ps.rolling_resistance[b] * dt * inv_inertia.x, along) * u;
      }
      ps.angular_velocity[b] = w;
      ps.angular_momentum[b] = ps.inertia[b].x * w;
      continue;
    }
    // One rotation matrix serves every frame change: momentum, spin direction and the new
    // angular velocity. The cap is linear in L, so it is applied in both frames at once.
    const Mat3 r = to_matrix(ps.orientation[b]);
    Vec3 l = ps.angular_momentum[b] + ps.torque[b] * dt;
    Vec3 l_body = transpose_times(r, l);
    // Constant directional rolling torque against the body's own spin, capped so that it can
    // stop the spin within this step but never reverse it (physics.md: the CDT sign flip).
    if (resisted) {
      const Vec3 u = omega / w0;
      const Vec3 u_body = transpose_times(r, u);
      const double along = dot(scale(inv_inertia, l_body), u_body);  // new spin along u [rad/s]
      if (along > 0.0) {
        const double inertia_u = dot(scale(ps.inertia[b], u_body), u_body);  // moment about u [kg m2]
        const double dl = std::min(ps.rolling_resistance[b] * dt, along * inertia_u);
        l -= dl * u;
        l_body -= dl * u_body;
      }
    }
    ps.angular_momentum[b] = l;
    ps.angular_velocity[b] = r * scale(inv_inertia, l_body);
  }
}

void Simulation::drift(double dt) {
  auto& ps = particles_;
  const std::size_t nb = ps.bodies();
  constexpr std::size_t block = RotationBatch::capacity;
  const auto blocks = static_cast<std::ptrdiff_t>((nb + block - 1) / block);
  double moved2 = 0.0;  // largest squared displacement of an element since the last build [m2]
#pragma omp parallel for schedule(static) reduction(max : moved2) if (nb > parallel_threshold)
  for (std::ptrdiff_t k0 = 0; k0 < blocks; ++k0) {
    // The elements are measured against the neighbour list's skin while at hand (declared in
    // the loop so that it updates this thread's copy of moved2).
    const auto measure = [&](std::uint32_t s, const Vec3& p) {
      const double d2 = neighbors_.displacement2(s, p);
      element_moved2_[s] = d2;  // bounds the part-face distances (find_part_candidates)
      moved2 = std::max(moved2, d2);
    };
    // The block's clumps with anisotropic inertia rotate together (rotation_batch.hpp); each
    // body's result does not depend on which others share its batch.
    RotationBatch batch;
    std::array<std::size_t, block> body;
    int n = 0;
    const std::size_t b0 = static_cast<std::size_t>(k0) * block, b1 = std::min(nb, b0 + block);
    for (std::size_t b = b0; b < b1; ++b) {
      ps.position[b] += ps.velocity[b] * dt;
      // A lone sphere's orientation changes nothing, so it is not advanced (as LIGGGHTS's
      // nve/sphere).
      if (ps.sphere_count[b] == 1) {
        ps.place_elements(b, measure);
        continue;
      }
      Quat& q = ps.orientation[b];
      if (is_isotropic(ps.inertia[b])) {
        q = advance(q, ps.angular_velocity[b], dt);  // omega is constant
        ps.place_elements(b, to_matrix(q), measure);
        continue;
      }
      const Vec3 &w = ps.angular_velocity[b], &ii = ps.inverse_inertia[b], &l = ps.angular_momentum[b];
      batch.qw[n] = q.w, batch.qx[n] = q.x, batch.qy[n] = q.y, batch.qz[n] = q.z;
      batch.wx[n] = w.x, batch.wy[n] = w.y, batch.wz[n] = w.z;
      batch.ix[n] = ii.x, batch.iy[n] = ii.y, batch.iz[n] = ii.z;
      batch.lx[n] = l.x, batch.ly[n] = l.y, batch.lz[n] = l.z;
      body[static_cast<std::size_t>(n++)] = b;
    }
    batch.size = n;
    if (n > 0) rotate_rigid(batch, dt);
    for (int k = 0; k < n; ++k) {
      const std::size_t b = body[static_cast<std::size_t>(k)];
      ps.orientation[b] = {batch.qw[k], batch.qx[k], batch.qy[k], batch.qz[k]};
      const Mat3 r = to_matrix(ps.orientation[b]);
      ps.angular_velocity[b] = angular_velocity_from_momentum(r, ps.inverse_inertia[b], ps.angular_momentum[b]);
      ps.place_elements(b, r, measure);
    }
  }
  rebuild_due_ = neighbors_.needs_rebuild(moved2) ? 1 : 0;
}

void Simulation::step(std::uint64_t n) {
  prepare();
  rebuild_due_ = -1;  // particles may have been added or moved from outside: check them all
  const double dt = settings_.dt;
  for (std::uint64_t k = 0; k < n; ++k) {
    if (settings_.integrator == Integrator::velocity_verlet) {
      if (!forces_valid_) compute_forces(), update_servos();
      kick(0.5 * dt);
      drift(dt);
      move_parts(time_, dt);
      time_ += dt;
      compute_forces();
      update_servos();
      kick(0.5 * dt);
    } else {
      compute_forces();
      update_servos();
      kick(dt);
      drift(dt);
      move_parts(time_, dt);
      time_ += dt;
    }
    ++steps_;
  }
}

}  // namespace bushel
