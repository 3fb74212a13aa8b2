#include "bushel/integrate/simulation.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "bushel/core/input_error.hpp"
#include "coefficients.hpp"
#include "stages.hpp"

namespace bushel {
namespace {

// The adaptive skin's range, in shares of the largest element radius (0.11 and 0.35 of its
// diameter): the least ran the settled bed of the pour benchmark 13% faster than 0.25 d and
// the pour as fast (bench/results/engine-tuning.md); the neighbour stage widens it where particles move fast.
constexpr double skin_least_per_radius = 0.22;
constexpr double skin_most_per_radius = 0.70;

}  // namespace

Simulation::Simulation(SimulationSettings settings) : w_(std::make_unique<engine::World>()) {
  w_->settings = std::move(settings);
  w_->rolling = rolling_model(w_->settings.rolling);
  w_->team = engine::Team(w_->settings.threads);
  set_time_step(w_->settings.dt);  // (its check)
  if (w_->settings.skin < 0.0) throw InputError("expected a non-negative skin").with_key("skin");
  if (!(w_->settings.tangential_damping_limit > 0.0)) {
    throw InputError("expected a positive fraction, or infinity for none").with_key("tangential_damping_limit");
  }
}

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

ParticleSystem& Simulation::particles() { return w_->particles; }
const ParticleSystem& Simulation::particles() const { return w_->particles; }
const Part& Simulation::part(std::size_t i) const { return w_->parts[i]; }
std::size_t Simulation::parts() const { return w_->parts.size(); }
double Simulation::time() const { return w_->time; }
std::uint64_t Simulation::steps() const { return w_->steps; }
const SimulationSettings& Simulation::settings() const { return w_->settings; }
ThreadStatus Simulation::threads() const { return w_->team.status(); }
double Simulation::max_overlap_ratio() const { return w_->diagnostics.max_overlap_ratio; }
double Simulation::peak_overlap_ratio() const { return w_->diagnostics.peak_overlap_ratio; }
void Simulation::reset_peak_overlap_ratio() { w_->diagnostics.peak_overlap_ratio = 0.0; }
std::size_t Simulation::contacts() const { return w_->diagnostics.contacts; }
const NeighborList& Simulation::neighbors() const { return w_->neighbors; }
double Simulation::unbalanced_force_ratio() const {
  return engine::unbalanced_force_ratio(w_->particles, w_->sums, w_->diagnostics);
}
namespace {
const Vec3 no_force{};
}  // namespace
const Vec3& Simulation::body_force(std::size_t b) const {
  return engine::has_sums(w_->particles, w_->sums, b) ? engine::body_force(w_->particles, w_->sums, b) : no_force;
}
const Vec3& Simulation::body_torque(std::size_t b) const {
  return engine::has_sums(w_->particles, w_->sums, b) ? engine::body_torque(w_->particles, w_->sums, b) : no_force;
}

void Simulation::set_time_step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw InputError("expected a positive time step").with_key("dt");
  w_->settings.dt = dt;
}

std::size_t Simulation::add_part(Part part) {
  const std::string key = "parts." + part.name;
  if (part.name.empty()) throw InputError("expected a name for every geometry part").with_key("parts");
  for (const Part& other : w_->parts) {
    if (other.name == part.name) throw InputError("two geometry parts are called '" + part.name + "'").with_key(key);
  }
  try {
    validate(part.material);
    validate_motion(part.shape, part.motion);
    const Quat& q = part.pose.orientation;
    if (!std::isfinite(norm(part.pose.position)) || !std::isfinite(norm2(q)) || norm2(q) < 1e-12) {
      throw InputError("expected a finite position in m and a non-zero finite orientation quaternion").with_key("pose");
    }
    part.pose.orientation = normalized(part.pose.orientation);
    w_->geometry.push_back(engine::make_part_geometry(part));
    part.twist = twist_at(part.motion, 0.0, part.pose, w_->time);
  } catch (const InputError& e) {
    throw e.with_key(key);
  }
  w_->parts.push_back(std::move(part));
  w_->candidates.stale = true;
  w_->forces_valid = false;  // (the part's reactions are not in the last forces)
  return w_->parts.size() - 1;
}

std::size_t Simulation::part_index(const std::string& name) const {
  std::string names;
  for (std::size_t i = 0; i < w_->parts.size(); ++i) {
    if (w_->parts[i].name == name) return i;
    names += (i ? ", " : "") + w_->parts[i].name;
  }
  throw InputError("no geometry part called '" + name + "' (parts: " + names + ")").with_key("parts");
}

void Simulation::set_motion(std::size_t i, Motion motion) {
  Part& part = w_->parts.at(i);
  try {
    validate_motion(part.shape, motion);
  } catch (const InputError& e) {
    throw e.with_key("parts." + part.name);
  }
  part.motion = std::move(motion);
  part.servo = {};
  part.twist = twist_at(part.motion, 0.0, part.pose, w_->time);
}

void Simulation::set_part_enabled(std::size_t i, bool enabled) {
  if (i >= w_->parts.size()) throw std::out_of_range("Simulation::set_part_enabled: no such part");
  if (w_->parts[i].enabled == enabled) return;
  w_->parts[i].enabled = enabled;
  w_->candidates.stale = true;  // the candidates are found again before the next contacts
}

TriangleMesh Simulation::part_surface(std::size_t i, int segments, double plane_half_size) const {
  const engine::PartGeometry& g = w_->geometry.at(i);
  TriangleMesh m = tessellate(g.faces, segments, plane_half_size);
  for (Vec3& v : m.vertices) v = w_->parts[i].pose.position + g.rotation * v;
  return m;
}

std::uint32_t Simulation::add_type(ParticleType type) { return w_->particles.add_type(std::move(type)); }

std::uint32_t Simulation::add_body(std::uint32_t type, const BodyState& state) {
  const std::uint32_t id = w_->particles.add(type, state);
  w_->forces_valid = false;  // (velocity Verlet's first half kick needs the new body's force)
  return id;
}

void Simulation::prepare_steps() {
  engine::World& w = *w_;
  const auto& types = w.particles.types();
  if (types.size() != w.configured.types || w.parts.size() != w.configured.parts) {
    w.coefficients = engine::make_coefficients(w.settings.contacts, types, w.parts);
    if (!w.configured.neighbors && !types.empty()) {
      // The skin's range follows the largest element of the first types; the cell size of
      // later builds follows the largest element present, so adding bigger types stays correct.
      double r_max = 0.0;
      for (const auto& t : types) {
        for (const auto& e : t.shape.spheres) r_max = std::max(r_max, e.radius);
      }
      const double fixed = w.settings.skin;
      w.skin.least = fixed > 0.0 ? fixed : skin_least_per_radius * r_max;
      w.skin.most = fixed > 0.0 ? fixed : skin_most_per_radius * r_max;
      w.neighbors = NeighborList(w.skin.least, history_size(w.rolling));
      w.configured.neighbors = true;
    }
    w.configured.types = types.size();
    w.configured.parts = w.parts.size();
  }
  const std::size_t n_s = w.particles.spheres();
  engine::ContactSums& s = w.sums;
  s.element.resize(n_s);
  s.second_direct.resize(n_s);
  w.particles.update_sphere_positions();
  // Particles may have been added or moved from outside: their displacements are measured.
  w.displacements = engine::Displacements::unknown;
}

void Simulation::remove_bodies(std::span<const std::size_t> bodies) {
  if (bodies.empty()) return;
  ParticleSystem& ps = w_->particles;
  const std::size_t n = ps.bodies();
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
  engine::permute_body_sums(w_->sums, ps.permute(keep));  // a permutation onto a subset drops the rest
  // The neighbour list and the part candidates index elements: both are found again now
  // (their histories follow the stable ids), so that what reads them between steps (a
  // sensor) sees the bodies that remain; the stored forces belong to the old bodies.
  prepare_steps();
  engine::rebuild_neighbors(*w_, false);
  w_->forces_valid = false;
}

void Simulation::compute_forces() {
  engine::World& w = *w_;
  engine::update_neighbors(w);
  engine::compute_contacts(w);
  engine::sum_part_reactions(w.candidates, w.parts, w.diagnostics);
  engine::gather(w.particles, w.sums, w.settings.gravity);
  w.forces_valid = true;
  engine::update_servos(w.parts, w.time);
}

void Simulation::step(std::uint64_t n) {
  prepare_steps();
  engine::World& w = *w_;
  const double dt = w.settings.dt;
  // A kick over kick_dt, then the drift and the parts over dt: the displacements since the
  // build are measured on the way.
  auto kick_drift_move = [&](double kick_dt) {
    engine::kick(w.particles, w.sums, kick_dt);
    w.displacements = engine::drift(w.particles, w.neighbors, dt);
    engine::move_parts(w.parts, w.geometry, w.neighbors.skin(), w.time, dt, w.candidates);
    w.time += dt;
  };
  w.team.enter();
  struct Leave {  // the caller's thread count back, also when a step throws
    engine::Team& team;
    ~Leave() { team.leave(); }
  } leave{w.team};
  for (std::uint64_t k = 0; k < n; ++k) {
    w.team.before_step();
    if (w.settings.integrator == Integrator::velocity_verlet) {
      if (!w.forces_valid) compute_forces();
      kick_drift_move(0.5 * dt);
      compute_forces();
      engine::kick(w.particles, w.sums, 0.5 * dt);
    } else {
      compute_forces();
      kick_drift_move(dt);
    }
    ++w.steps;
  }
}

}  // namespace bushel
