#include "bushel/particles/particle_system.hpp"

#include <algorithm>
#include <stdexcept>

#include "bushel/core/input_error.hpp"
#include "bushel/core/parallel.hpp"
#include "bushel/io/binary_archive.hpp"

namespace bushel {
namespace {

template <class T>
void apply(std::vector<T>& v, std::span<const std::uint32_t> order) {
  std::vector<T> out(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) out[i] = v[order[i]];
  v = std::move(out);
}

}  // namespace

std::uint32_t ParticleSystem::add_type(ParticleType type) {
  validate(type.material);
  const Vec3 moments = type.shape.principal_inertia(type.material.density);
  type_mass_.push_back(type.mass());
  type_inertia_.push_back(moments);
  type_inverse_inertia_.push_back({1.0 / moments.x, 1.0 / moments.y, 1.0 / moments.z});
  type_first_offset_.push_back(static_cast<std::uint32_t>(type_offsets_.size()));
  for (const auto& e : type.shape.spheres) type_offsets_.push_back(e.centre);
  const bool clump = type.shape.spheres.size() > 1;
  types_.push_back(std::move(type));
  if (clump && !keeps_rotation_) {  // the lone spheres so far: their derived rotation from now on kept
    orientation = orientations();
    angular_momentum = angular_momenta();
    keeps_rotation_ = true;
  }
  return static_cast<std::uint32_t>(types_.size() - 1);
}

std::uint32_t ParticleSystem::add(std::uint32_t type, const BodyState& s) {
  if (type >= types_.size()) throw std::out_of_range("ParticleSystem::add: unknown particle type");
  const ParticleType& t = types_[type];
  const auto b = static_cast<std::uint32_t>(bodies());
  body_id.push_back(next_body_id_++);
  body_type.push_back(type);
  position.push_back(s.position);
  const Quat q = normalized(s.orientation);
  velocity.push_back(s.velocity);
  angular_velocity.push_back(s.angular_velocity);
  if (keeps_rotation_) {
    orientation.push_back(q);
    angular_momentum.push_back(spin_momentum(b));
  }
  first_sphere.push_back(static_cast<std::uint32_t>(spheres()));
  sphere_count.push_back(static_cast<std::uint32_t>(t.shape.spheres.size()));
  for (const auto& e : t.shape.spheres) {
    sphere_id.push_back(next_sphere_id_++);
    owner.push_back(b);
    species.push_back(type);
    radius.push_back(e.radius);
    sphere_position.push_back(s.position + rotate(q, e.centre));
  }
  return body_id.back();
}

void ParticleSystem::update_sphere_positions() {
  const auto n = static_cast<std::ptrdiff_t>(bodies());
#pragma omp parallel for schedule(static) if (static_cast <std::ptrdiff_t>(spheres()) > parallel_threshold)
  for (std::ptrdiff_t b = 0; b < n; ++b) place_elements(static_cast<std::size_t>(b), [](std::uint32_t, const Vec3&) {});
}

std::vector<std::uint32_t> ParticleSystem::permute(std::span<const std::uint32_t> order) {
  std::vector<std::uint32_t> sphere_order;
  sphere_order.reserve(spheres());
  std::vector<std::uint32_t> new_first(order.size());
  for (std::size_t nb = 0; nb < order.size(); ++nb) {
    const std::uint32_t ob = order[nb];
    new_first[nb] = static_cast<std::uint32_t>(sphere_order.size());
    for (std::uint32_t k = 0; k < sphere_count[ob]; ++k) sphere_order.push_back(first_sphere[ob] + k);
  }
  for (auto* v : {&body_id, &body_type, &sphere_count}) apply(*v, order);
  for (auto* v : {&position, &velocity, &angular_velocity}) apply(*v, order);
  if (keeps_rotation_) apply(angular_momentum, order), apply(orientation, order);
  first_sphere = std::move(new_first);
  for (auto* v : {&sphere_id, &species}) apply(*v, sphere_order);
  apply(sphere_position, sphere_order);
  apply(radius, sphere_order);
  owner.resize(sphere_order.size());  // fewer elements when `order` keeps a subset
  for (std::size_t b = 0; b < bodies(); ++b) {
    for (std::uint32_t k = 0; k < sphere_count[b]; ++k) owner[first_sphere[b] + k] = static_cast<std::uint32_t>(b);
  }
  return sphere_order;
}

std::vector<Quat> ParticleSystem::orientations() const {
  return keeps_rotation_ ? orientation : std::vector<Quat>(bodies());
}

std::vector<Vec3> ParticleSystem::angular_momenta() const {
  if (keeps_rotation_) return angular_momentum;
  std::vector<Vec3> l(bodies());
  for (std::size_t b = 0; b < l.size(); ++b) l[b] = angular_momentum_of(b);
  return l;
}

double ParticleSystem::rotational_energy(std::size_t b) const {
  const Vec3 w = rotate_inverse(orientation_of(b), angular_velocity[b]);  // body frame
  const Vec3& i = inertia(b);
  return 0.5 * (i.x * w.x * w.x + i.y * w.y * w.y + i.z * w.z * w.z);
}

Vec3 ParticleSystem::spin_momentum(std::size_t b) const {
  const Quat q = orientation_of(b);
  const Vec3 w = rotate_inverse(q, angular_velocity[b]);
  const Vec3& i = inertia(b);
  return rotate(q, Vec3{i.x * w.x, i.y * w.y, i.z * w.z});
}

double ParticleSystem::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t b = 0; b < bodies(); ++b) e += 0.5 * mass(b) * norm2(velocity[b]) + rotational_energy(b);
  return e;
}

void ParticleSystem::save(io::BinaryWriter& out) const {
  out.put(static_cast<std::uint64_t>(types_.size()));
  out.put(next_body_id_);
  out.put(next_sphere_id_);
  out.put(body_id);
  out.put(body_type);
  out.put(position);
  out.put(orientations());  // (kept or derived: the same section either way)
  out.put(velocity);
  out.put(angular_velocity);
  out.put(angular_momenta());
  out.put(type_mass_);  // (for the check on load: the bodies' masses are their types')
  out.put(first_sphere);
  out.put(sphere_count);
  out.put(sphere_id);
  out.put(owner);
  out.put(species);
  out.put(radius);
  out.put(sphere_position);
}

ParticleSystem::SavedForces ParticleSystem::load(io::BinaryReader& in, std::uint32_t version) {
  if (in.get<std::uint64_t>() != types_.size()) {
    throw InputError("the checkpoint has another number of particle types than the scenario");
  }
  in.get(next_body_id_);
  in.get(next_sphere_id_);
  in.get(body_id);
  in.get(body_type);
  in.get(position);
  in.get(orientation);
  in.get(velocity);
  in.get(angular_velocity);
  in.get(angular_momentum);
  SavedForces saved;
  std::vector<double> masses;  // versions 1 and 2: per body; 3: per type
  if (version < 3) in.get(saved.force), in.get(saved.torque), in.get(saved.rolling_resistance);
  in.get(masses);
  std::vector<Vec3> moments, inverse_moments, centres;  // (version 1: per body and element)
  if (version == 1) in.get(moments), in.get(inverse_moments);
  in.get(first_sphere);
  in.get(sphere_count);
  in.get(sphere_id);
  in.get(owner);
  in.get(species);
  if (version == 1) in.get(centres);
  in.get(radius);
  in.get(sphere_position);
  // A damaged file must not index out of bounds later.
  const std::size_t nb = body_id.size(), ns = sphere_id.size();
  bool ok = true;
  for (const std::size_t n :
       {body_type.size(), position.size(), orientation.size(), velocity.size(), angular_velocity.size(),
        angular_momentum.size(), first_sphere.size(), sphere_count.size()}) {
    ok = ok && n == nb;
  }
  if (version < 3) {
    for (const std::size_t n : {saved.force.size(), saved.torque.size(), saved.rolling_resistance.size()}) {
      ok = ok && n == nb;
    }
  }
  ok = ok && masses.size() == (version < 3 ? nb : types_.size());
  for (const std::size_t n : {owner.size(), species.size(), radius.size(), sphere_position.size()}) ok = ok && n == ns;
  for (std::size_t b = 0; ok && b < nb; ++b) {
    ok = body_type[b] < types_.size() && std::size_t{first_sphere[b]} + sphere_count[b] <= ns &&
         sphere_count[b] == types_[body_type[b]].shape.spheres.size();
  }
  for (std::size_t s = 0; ok && s < ns; ++s) ok = owner[s] < nb && species[s] == body_type[owner[s]];
  if (!ok) throw InputError("the checkpoint's particles are inconsistent (a damaged file?)");
  if (!keeps_rotation_) {  // (lone spheres only: derived)
    std::vector<Quat>().swap(orientation);
    std::vector<Vec3>().swap(angular_momentum);
  }
  if (version >= 3) {  // per type: per body, for the check
    std::vector<double> by_body(nb);
    for (std::size_t b = 0; b < nb; ++b) by_body[b] = masses[body_type[b]];
    masses = std::move(by_body);
  }
  check_type_shapes(masses, version == 1, moments, inverse_moments, centres);
  return saved;
}

void ParticleSystem::check_type_shapes(std::span<const double> masses, bool with_moments, std::span<const Vec3> moments,
                                       std::span<const Vec3> inverse_moments, std::span<const Vec3> centres) const {
  bool same = !with_moments ||
              (moments.size() == bodies() && inverse_moments.size() == bodies() && centres.size() == spheres());
  for (std::size_t b = 0; same && b < bodies(); ++b) {
    const ParticleType& t = types_[body_type[b]];
    same = masses[b] == t.mass();
    for (std::uint32_t k = 0; same && k < sphere_count[b]; ++k)
      same = radius[first_sphere[b] + k] == t.shape.spheres[k].radius;
    same = same &&
           (!with_moments || (moments[b] == inertia(b) && inverse_moments[b] == inverse_inertia(b) &&
                              std::equal(offsets(b).begin(), offsets(b).end(), centres.begin() + first_sphere[b])));
  }
  if (!same) {
    throw InputError("the checkpoint's particles have other shapes or densities than the scenario's particle types");
  }
}

}  // namespace bushel
