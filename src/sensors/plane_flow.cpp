#include "bushel/sensors/plane_flow.hpp"

#include "bushel/io/binary_archive.hpp"

namespace bushel {

PlaneFlow::PlaneFlow(const Vec3& point, const Vec3& normal, double window)
    : point_(point), normal_(normal), window_(window) {}

void PlaneFlow::update(const ParticleSystem& ps, double t) {
  for (std::size_t b = 0; b < ps.bodies(); ++b) {
    const std::uint32_t id = ps.body_id[b];
    if (id >= side_.size()) side_.resize(id + 1, 0);
    const std::int8_t s = dot(ps.position[b] - point_, normal_) >= 0.0 ? 1 : -1;
    if (side_[id] != 0 && side_[id] != s) mass_ += s * ps.mass(b);
    side_[id] = s;
  }
  samples_.add(t, mass_, window_);
}

double PlaneFlow::rate() const { return samples_.slope(); }

void PlaneFlow::save(io::BinaryWriter& out) const {
  out.put(mass_);
  out.put(side_);
  out.put(samples_.time);
  out.put(samples_.value);
}

void PlaneFlow::load(io::BinaryReader& in) {
  in.get(mass_);
  in.get(side_);
  in.get(samples_.time);
  in.get(samples_.value);
}

}  // namespace bushel
