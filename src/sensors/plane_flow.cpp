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
    if (side_[id] != 0 && side_[id] != s) mass_ += s * ps.mass[b];
    side_[id] = s;
  }
  time_.push_back(t);
  total_.push_back(mass_);
  // keep one sample at or before the window's start
  std::size_t drop = 0;
  while (time_.size() - drop > 2 && time_[drop + 1] <= t - window_) ++drop;
  time_.erase(time_.begin(), time_.begin() + static_cast<std::ptrdiff_t>(drop));
  total_.erase(total_.begin(), total_.begin() + static_cast<std::ptrdiff_t>(drop));
}

double PlaneFlow::rate() const {
  if (time_.size() < 2 || !(time_.back() > time_.front())) return 0.0;
  return (total_.back() - total_.front()) / (time_.back() - time_.front());
}

void PlaneFlow::save(io::BinaryWriter& out) const {
  out.put(mass_);
  out.put(side_);
  out.put(time_);
  out.put(total_);
}

void PlaneFlow::load(io::BinaryReader& in) {
  in.get(mass_);
  in.get(side_);
  in.get(time_);
  in.get(total_);
}

}  // namespace bushel
