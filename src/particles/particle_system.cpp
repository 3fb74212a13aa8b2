#include "bushel/particles/particle_system.hpp"

#include <stdexcept>

#include "bushel/core/parallel.hpp"

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
  types_.push_back(std::move(type));
  return static_cast<std::uint32_t>(types_.size() - 1);
}

std::uint32_t ParticleSystem::add(std::uint32_t type, const BodyState& s) {
  if (type >= types_.size()) throw std::out_of_range("ParticleSystem::add: unknown particle type");
  const ParticleType& t = types_[type];
  const auto b = static_cast<std::uint32_t>(bodies());
  body_id.push_back(next_body_id_++);
  body_type.push_back(type);
  position.push_back(s.position);
  orientation.push_back(normalized(s.orientation));
  velocity.push_back(s.velocity);
  angular_velocity.push_back(s.angular_velocity);
  force.push_back({});
  torque.push_back({});
  rolling_resistance.push_back(0.0);
  mass.push_back(t.mass());
  inertia.push_back(t.shape.principal_inertia(t.material.density));
  inverse_inertia.push_back({1.0 / inertia.back().x, 1.0 / inertia.back().y, 1.0 / inertia.back().z});
  angular_momentum.push_back(spin_momentum(b));
  first_sphere.push_back(static_cast<std::uint32_t>(spheres()));
  sphere_count.push_back(static_cast<std::uint32_t>(t.shape.spheres.size()));
  for (const auto& e : t.shape.spheres) {
    sphere_id.push_back(next_sphere_id_++);
    owner.push_back(b);
    species.push_back(type);
    offset.push_back(e.centre);
    radius.push_back(e.radius);
    sphere_position.push_back(s.position + rotate(orientation.back(), e.centre));
  }
  return body_id.back();
}

void ParticleSystem::update_sphere_positions() {
  const auto n = static_cast<std::ptrdiff_t>(bodies());
#pragma omp parallel for schedule(static) if (n > parallel_threshold)
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
  for (auto* v :
       {&position, &velocity, &angular_velocity, &angular_momentum, &force, &torque, &inertia, &inverse_inertia}) {
    apply(*v, order);
  }
  apply(orientation, order);
  apply(mass, order);
  apply(rolling_resistance, order);
  first_sphere = std::move(new_first);
  for (auto* v : {&sphere_id, &species}) apply(*v, sphere_order);
  apply(offset, sphere_order);
  apply(sphere_position, sphere_order);
  apply(radius, sphere_order);
  owner.resize(sphere_order.size());  // fewer elements when `order` keeps a subset
  for (std::size_t b = 0; b < bodies(); ++b) {
    for (std::uint32_t k = 0; k < sphere_count[b]; ++k) owner[first_sphere[b] + k] = static_cast<std::uint32_t>(b);
  }
  return sphere_order;
}

double ParticleSystem::rotational_energy(std::size_t b) const {
  const Vec3 w = rotate_inverse(orientation[b], angular_velocity[b]);  // body frame
  return 0.5 * (inertia[b].x * w.x * w.x + inertia[b].y * w.y * w.y + inertia[b].z * w.z * w.z);
}

Vec3 ParticleSystem::spin_momentum(std::size_t b) const {
  const Vec3 w = rotate_inverse(orientation[b], angular_velocity[b]);
  return rotate(orientation[b], Vec3{inertia[b].x * w.x, inertia[b].y * w.y, inertia[b].z * w.z});
}

double ParticleSystem::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t b = 0; b < bodies(); ++b) e += 0.5 * mass[b] * norm2(velocity[b]) + rotational_energy(b);
  return e;
}

}  // namespace bushel
