#include "bushel/integrate/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <type_traits>

#include "bushel/contact/hertz_mindlin.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/core/parallel.hpp"
#include "bushel/integrate/rigid_rotation.hpp"

namespace bushel {
namespace {

Vec3 load3(const double* h) { return {h[0], h[1], h[2]}; }
void store3(double* h, const Vec3& v) { h[0] = v.x, h[1] = v.y, h[2] = v.z; }
double min_moment(const Vec3& i) { return std::min({i.x, i.y, i.z}); }
// Equal principal moments (a sphere): L = I omega in any frame, so rotation needs no quaternion work.
bool is_isotropic(const Vec3& i) { return i.x == i.y && i.y == i.z; }

// One Hertz-Mindlin contact with rolling model R, shared by sphere-sphere and sphere-wall
// contacts: everything about the pair comes in, the force on side i and the rolling output
// come out, and the history (tangential displacement, then the model's values) is updated.
struct ContactKinematics {
  Vec3 normal;     // unit, from i towards j
  double overlap;  // [m]
  Vec3 v_rel;      // velocity of i's contact point minus j's [m/s]
  Vec3 omega_i, omega_j;
  double arm_i, arm_j;
  double r_star, m_star, inertia_r;
};

template <class Rolling>
Vec3 contact_force(const ContactKinematics& k, const PairCoefficients& c, double dt, double* history,
                   RollingOutput& rolling) {
  const double v_n = dot(k.v_rel, k.normal);  // approach speed: i moves towards j
  const Vec3 v_t = k.v_rel - v_n * k.normal;
  double s_n = 0.0, root_s_n_m = 0.0;
  const double f_n =
      hertz_mindlin::normal_force(c.youngs_modulus, k.r_star, k.m_star, c.damping, k.overlap, v_n, s_n, root_s_n_m);
  Vec3 xi = load3(history);
  const Vec3 f_t = hertz_mindlin::tangential_force(k.normal, v_t, s_n, root_s_n_m, c.stiffness_ratio,
                                                   c.root_stiffness_ratio, c.damping, f_n, c.static_friction, dt, xi);
  store3(history, xi);
  Vec3 spring = Rolling::history_size ? load3(history + 3) : Vec3{};
  rolling = Rolling::torque(
      {k.normal, k.omega_i, k.omega_j, k.arm_i, k.arm_j, k.r_star, f_n, s_n, c.rolling_friction, k.inertia_r, dt},
      spring);
  if constexpr (Rolling::history_size > 0) store3(history + 3, spring);
  return -f_n * k.normal + f_t;
}

}  // namespace

Simulation::Simulation(SimulationSettings settings)
    : settings_(std::move(settings)), rolling_(rolling_model(settings_.rolling)), neighbors_(1.0, 3) {
  if (!(settings_.dt > 0.0)) throw InputError("expected a positive time step").with_key("dt");
  if (settings_.skin < 0.0) throw InputError("expected a non-negative skin").with_key("skin");
}

std::size_t Simulation::add_wall(Wall wall) {
  validate(wall.material);
  walls_.push_back(std::move(wall));
  return walls_.size() - 1;
}

void Simulation::prepare() {
  const auto& types = particles_.types();
  if (types.size() != prepared_types_ || walls_.size() != prepared_walls_) {
    std::vector<Species> species;
    std::vector<const Material*> materials;
    for (const auto& t : types) {
      species.push_back({t.name, t.material.name});
      materials.push_back(&t.material);
    }
    for (const auto& w : walls_) {
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
    if (walls_.size() != prepared_walls_) {  // the history layout changes with the wall count
      wall_history_.clear();
      walls_changed_ = true;
    }
    if (!neighbors_configured_ && !types.empty()) {
      // The default skin is 0.11 of the largest element diameter (0.40 mm for 3.64 mm
      // spheres): on the pour benchmark it ran the settled bed 13% faster than 0.25 d and the
      // pour as fast (bench/README.md). The cell size of later builds follows the largest
      // element present, so adding bigger types stays correct.
      double skin = settings_.skin;
      if (skin == 0.0) {
        for (const auto& t : types) {
          for (const auto& e : t.shape.spheres) skin = std::max(skin, 0.22 * e.radius);
        }
      }
      neighbors_ = NeighborList(skin, history_size(rolling_));
      neighbors_configured_ = true;
    }
    prepared_types_ = types.size();
    prepared_walls_ = walls_.size();
  }
  const std::size_t h = static_cast<std::size_t>(neighbors_.history_size());
  const std::size_t n_s = particles_.spheres(), n_w = walls_.size();
  wall_history_.resize(n_s * n_w * h, 0.0);  // new elements append their (zero) history
  particles_.update_sphere_positions();
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
  const std::vector<std::uint32_t> sphere_order = ps.permute(order);
  const std::size_t block = walls_.size() * static_cast<std::size_t>(neighbors_.history_size());
  if (block > 0) {
    std::vector<double> h(wall_history_.size());
    for (std::size_t s = 0; s < sphere_order.size(); ++s) {
      std::copy_n(wall_history_.data() + sphere_order[s] * block, block, h.data() + s * block);
    }
    wall_history_ = std::move(h);
  }
}

void Simulation::rebuild() {
  if (settings_.sort_every > 0 && neighbors_.builds() % static_cast<std::size_t>(settings_.sort_every) == 0) {
    spatial_sort();
  }
  const auto& ps = particles_;
  neighbors_.build(ps.sphere_position, ps.radius, ps.owner, ps.sphere_id);
  find_wall_candidates();
}

void Simulation::find_wall_candidates() {
  // Walls are still and no element moves more than half the skin before the next build, so
  // a sphere further than the skin from a wall cannot reach it before then.
  const auto& ps = particles_;
  const std::size_t n_s = ps.spheres(), n_w = walls_.size();
  const auto h = static_cast<std::size_t>(neighbors_.history_size());
  const double skin = neighbors_.skin();
  wall_start_.assign(n_s + 1, 0);
  wall_of_candidate_.clear();
  for (std::size_t s = 0; s < n_s; ++s) {
    for (std::size_t w = 0; w < n_w; ++w) {
      if (clearance(walls_[w], ps.sphere_position[s], ps.radius[s]) < skin) {
        wall_of_candidate_.push_back(static_cast<std::uint32_t>(w));
      } else {  // out of reach: any history left is stale
        std::fill_n(wall_history_.data() + (s * n_w + w) * h, h, 0.0);
      }
    }
    wall_start_[s + 1] = static_cast<std::uint32_t>(wall_of_candidate_.size());
  }
  const std::size_t n_c = wall_of_candidate_.size();
  wall_force_.assign(n_c, Vec3{});
  wall_torque_.assign(n_c, Vec3{});
  wall_cdt_.assign(n_c, 0.0);
  wall_reaction_.assign(2 * n_c, Vec3{});
  walls_changed_ = false;
}

template <class Rolling>
void Simulation::compute_forces(const Rolling&) {
  auto& ps = particles_;
  const double dt = settings_.dt;
  const std::size_t n_pairs = neighbors_.pairs();
  pair_force_.resize(n_pairs);
  pair_torque_i_.resize(n_pairs);
  pair_torque_j_.resize(n_pairs);
  pair_cdt_i_.resize(n_pairs);
  pair_cdt_j_.resize(n_pairs);
  if (neighbors_.builds() != active_build_) {
    // A new list: every pair counts as touching once, so that where it does not, its history
    // and outputs are zeroed; from then on only pairs whose contact ends write zeros, and the
    // gather reads every pair without a (badly predicted) branch.
    pair_active_.assign(n_pairs, 1);
    active_build_ = neighbors_.builds();
  }
  const int h = neighbors_.history_size();
  double max_ratio = 0.0;
  std::size_t touching = 0;

  // --- sphere-sphere ------------------------------------------------------------------------
  const auto np = static_cast<std::ptrdiff_t>(n_pairs);
#pragma omp parallel for schedule(static) reduction(max : max_ratio) reduction(+ : touching) if (np > parallel_threshold)
  for (std::ptrdiff_t sp = 0; sp < np; ++sp) {
    const auto p = static_cast<std::size_t>(sp);
    const std::uint32_t i = neighbors_.first(p), j = neighbors_.second(p);
    double* hist = neighbors_.history(p);
    const Vec3 d = ps.sphere_position[j] - ps.sphere_position[i];
    const double ri = ps.radius[i], rj = ps.radius[j];
    const double dist2 = norm2(d);
    if (dist2 >= (ri + rj) * (ri + rj)) {
      if (pair_active_[p]) {  // contact over: history starts afresh, outputs read as zero
        std::fill_n(hist, h, 0.0);
        pair_force_[p] = pair_torque_i_[p] = pair_torque_j_[p] = Vec3{};
        pair_cdt_i_[p] = pair_cdt_j_[p] = 0.0;
        pair_active_[p] = 0;
      }
      continue;
    }
    pair_active_[p] = 1;
    ++touching;
    const double dist = std::sqrt(dist2);
    const Vec3 n = d / dist;
    const double overlap = ri + rj - dist;
    max_ratio = std::max(max_ratio, overlap / std::min(ri, rj));
    const std::uint32_t bi = ps.owner[i], bj = ps.owner[j];
    const Vec3 c = ps.sphere_position[i] + (ri - 0.5 * overlap) * n;
    const Vec3 arm_i = c - ps.position[bi], arm_j = c - ps.position[bj];
    const Vec3 v_rel = ps.velocity[bi] + cross(ps.angular_velocity[bi], arm_i) - ps.velocity[bj] -
                       cross(ps.angular_velocity[bj], arm_j);
    const double mi = ps.mass[bi], mj = ps.mass[bj];
    // A lone sphere's centre of mass is its centre: the arm is r - delta/2, no square root.
    const double arm_i_len = ps.sphere_count[bi] == 1 ? ri - 0.5 * overlap : norm(arm_i);
    const double arm_j_len = ps.sphere_count[bj] == 1 ? rj - 0.5 * overlap : norm(arm_j);
    ContactKinematics k{n,
                        overlap,
                        v_rel,
                        ps.angular_velocity[bi],
                        ps.angular_velocity[bj],
                        arm_i_len,
                        arm_j_len,
                        ri * rj / (ri + rj),
                        mi * mj / (mi + mj),
                        0.0};
    if constexpr (std::is_same_v<Rolling, EpsdRolling>) {
      const double ii = min_moment(ps.inertia[bi]) + mi * k.arm_i * k.arm_i;
      const double ij = min_moment(ps.inertia[bj]) + mj * k.arm_j * k.arm_j;
      k.inertia_r = ii * ij / (ii + ij);
    }
    RollingOutput roll;
    const Vec3 f = contact_force<Rolling>(k, coefficients_(ps.species[i], ps.species[j]), dt, hist, roll);
    pair_force_[p] = f;
    pair_torque_i_[p] = cross(arm_i, f) + roll.torque_i;
    pair_torque_j_[p] = cross(arm_j, -f) + roll.torque_j;
    pair_cdt_i_[p] = roll.cdt_i;
    pair_cdt_j_[p] = roll.cdt_j;
  }

  // --- sphere-wall, over the candidates -------------------------------------------------------
  const std::size_t n_w = walls_.size();
  const std::size_t n_types = ps.types().size();
  const auto ns = static_cast<std::ptrdiff_t>(ps.spheres());
#pragma omp parallel for schedule(static) reduction(max : max_ratio) if (ns > parallel_threshold)
  for (std::ptrdiff_t ss = 0; ss < ns; ++ss) {
    const auto s = static_cast<std::size_t>(ss);
    const std::uint32_t b = ps.owner[s];
    for (std::uint32_t cw = wall_start_[s]; cw < wall_start_[s + 1]; ++cw) {
      const std::uint32_t w = wall_of_candidate_[cw];
      double* hist = wall_history_.data() + (s * n_w + w) * static_cast<std::size_t>(h);
      Vec3* reaction = wall_reaction_.data() + 2 * std::size_t{cw};
      const WallTouch t = touch(walls_[w], ps.sphere_position[s], ps.radius[s]);
      if (!t.touching) {
        if (std::any_of(hist, hist + h, [](double v) { return v != 0.0; })) std::fill_n(hist, h, 0.0);
        wall_force_[cw] = wall_torque_[cw] = reaction[0] = reaction[1] = Vec3{};
        wall_cdt_[cw] = 0.0;
        continue;
      }
      max_ratio = std::max(max_ratio, t.overlap / ps.radius[s]);
      const Vec3 arm = t.point - ps.position[b];
      const Vec3 v_rel = ps.velocity[b] + cross(ps.angular_velocity[b], arm);  // walls are still
      const double arm_len = norm(arm);
      ContactKinematics k{t.normal,   t.overlap,
                          v_rel,      ps.angular_velocity[b],
                          Vec3{},     arm_len,
                          0.0,        ps.radius[s],
                          ps.mass[b], min_moment(ps.inertia[b]) + ps.mass[b] * arm_len * arm_len};
      RollingOutput roll;
      const Vec3 f = contact_force<Rolling>(k, coefficients_(ps.species[s], n_types + w), dt, hist, roll);
      wall_force_[cw] = f;
      wall_torque_[cw] = cross(arm, f) + roll.torque_i;
      wall_cdt_[cw] = roll.cdt_i;
      reaction[0] = -f;
      reaction[1] = cross(t.point, -f) - roll.torque_i;
    }
  }
  sum_wall_reactions();

  // --- gather onto bodies, in a fixed order -------------------------------------------------
  const auto nb = static_cast<std::ptrdiff_t>(ps.bodies());
  const Vec3 g = settings_.gravity;
#pragma omp parallel for schedule(static) if (nb > parallel_threshold)
  for (std::ptrdiff_t sb = 0; sb < nb; ++sb) {
    const auto b = static_cast<std::size_t>(sb);
    Vec3 f = ps.mass[b] * g, t;
    double cdt = 0.0;
    for (std::uint32_t s = ps.first_sphere[b]; s < ps.first_sphere[b] + ps.sphere_count[b]; ++s) {
      for (const std::uint32_t p : neighbors_.pairs_of(s)) {
        if (neighbors_.first(p) == s) {
          f += pair_force_[p];
          t += pair_torque_i_[p];
          cdt += pair_cdt_i_[p];
        } else {
          f -= pair_force_[p];
          t += pair_torque_j_[p];
          cdt += pair_cdt_j_[p];
        }
      }
      for (std::uint32_t cw = wall_start_[s]; cw < wall_start_[s + 1]; ++cw) {
        f += wall_force_[cw];
        t += wall_torque_[cw];
        cdt += wall_cdt_[cw];
      }
    }
    ps.force[b] = f;
    ps.torque[b] = t;
    ps.rolling_resistance[b] = cdt;
  }
  max_overlap_ratio_ = max_ratio;
  contacts_ = touching;
  forces_valid_ = true;
}

void Simulation::sum_wall_reactions() {
  // Fixed chunks of candidates, summed in order: the same sums for any thread count, without
  // a serial pass over every candidate.
  const std::size_t n_w = walls_.size(), n_c = wall_of_candidate_.size();
  if (n_w == 0) return;
  constexpr std::size_t chunks = 64;
  const std::size_t per_chunk = (n_c + chunks - 1) / chunks;
  wall_partial_.assign(2 * chunks * n_w, Vec3{});
  const auto nc = static_cast<std::ptrdiff_t>(chunks);
#pragma omp parallel for schedule(static) if (static_cast <std::ptrdiff_t>(n_c) > parallel_threshold)
  for (std::ptrdiff_t sc = 0; sc < nc; ++sc) {
    const auto k = static_cast<std::size_t>(sc);
    Vec3* out = wall_partial_.data() + 2 * k * n_w;
    for (std::size_t c = k * per_chunk; c < std::min(n_c, (k + 1) * per_chunk); ++c) {
      const std::uint32_t w = wall_of_candidate_[c];
      out[2 * w] += wall_reaction_[2 * c];
      out[2 * w + 1] += wall_reaction_[2 * c + 1];
    }
  }
  for (std::size_t w = 0; w < n_w; ++w) {
    Vec3 f, t;
    for (std::size_t k = 0; k < chunks; ++k) {
      f += wall_partial_[2 * (k * n_w + w)];
      t += wall_partial_[2 * (k * n_w + w) + 1];
    }
    walls_[w].force = f;
    walls_[w].torque = t;
  }
}

void Simulation::compute_forces() {
  if (walls_changed_ || neighbors_.needs_rebuild(particles_.sphere_position)) rebuild();
  std::visit([this](const auto& model) { compute_forces(model); }, rolling_);
}

void Simulation::kick(double dt) {
  auto& ps = particles_;
  const auto nb = static_cast<std::ptrdiff_t>(ps.bodies());
#pragma omp parallel for schedule(static) if (nb > parallel_threshold)
  for (std::ptrdiff_t sb = 0; sb < nb; ++sb) {
    const auto b = static_cast<std::size_t>(sb);
    ps.velocity[b] += ps.force[b] * (dt / ps.mass[b]);
    const Vec3& inertia = ps.inertia[b];
    const Vec3 omega = ps.angular_velocity[b];
    if (is_isotropic(inertia)) {  // same cap as below, in omega instead of L
      Vec3 w = omega + ps.torque[b] * (dt / inertia.x);
      const double w0 = norm(omega);
      if (ps.rolling_resistance[b] > 0.0 && w0 > 0.0) {
        const Vec3 u = omega / w0;
        const double along = dot(w, u);
        if (along > 0.0) w -= std::min(ps.rolling_resistance[b] * dt / inertia.x, along) * u;
      }
      ps.angular_velocity[b] = w;
      ps.angular_momentum[b] = inertia.x * w;
      continue;
    }
    const Quat& q = ps.orientation[b];
    Vec3 l = ps.angular_momentum[b] + ps.torque[b] * dt;
    // Constant directional rolling torque against the body's own spin, capped so that it can
    // stop the spin within this step but never reverse it (physics.md: the CDT sign flip).
    const double w = norm(omega);
    if (ps.rolling_resistance[b] > 0.0 && w > 0.0) {
      const Vec3 u = omega / w;
      const double along = dot(angular_velocity_from_momentum(q, inertia, l), u);
      if (along > 0.0) l -= std::min(ps.rolling_resistance[b] * dt, along * inertia_about(q, inertia, u)) * u;
    }
    ps.angular_momentum[b] = l;
    ps.angular_velocity[b] = angular_velocity_from_momentum(q, inertia, l);
  }
}

void Simulation::drift(double dt) {
  auto& ps = particles_;
  const auto nb = static_cast<std::ptrdiff_t>(ps.bodies());
#pragma omp parallel for schedule(static) if (nb > parallel_threshold)
  for (std::ptrdiff_t sb = 0; sb < nb; ++sb) {
    const auto b = static_cast<std::size_t>(sb);
    ps.position[b] += ps.velocity[b] * dt;
    const Vec3& inertia = ps.inertia[b];
    if (is_isotropic(inertia)) {
      ps.orientation[b] = advance(ps.orientation[b], ps.angular_velocity[b], dt);  // omega is constant
    } else {
      ps.angular_velocity[b] =
          rotate_rigid(ps.orientation[b], inertia, ps.angular_momentum[b], ps.angular_velocity[b], dt);
    }
  }
  ps.update_sphere_positions();
}

void Simulation::step(std::uint64_t n) {
  prepare();
  const double dt = settings_.dt;
  for (std::uint64_t k = 0; k < n; ++k) {
    if (settings_.integrator == Integrator::velocity_verlet) {
      if (!forces_valid_) compute_forces();
      kick(0.5 * dt);
      drift(dt);
      compute_forces();
      kick(0.5 * dt);
    } else {
      compute_forces();
      kick(dt);
      drift(dt);
    }
    time_ += dt;
    ++steps_;
  }
}

}  // namespace bushel
