#pragma once
// Mass flow through a plane (the outlet of a funnel, the mouth of a spout): the net mass of
// particles whose centre of mass crossed the plane in the direction of its normal, and the
// flow rate over a recent window. Crossings are seen at each update (every check interval of
// a run), by the side of the plane each particle is on.

#include <cstdint>
#include <vector>

#include "bushel/core/sample_window.hpp"
#include "bushel/io/archive_fwd.hpp"
#include "bushel/particles/particle_system.hpp"

namespace bushel {

class PlaneFlow {
 public:
  /// The plane through `point` [m] with unit `normal`; the rate is averaged over `window` [s].
  PlaneFlow(const Vec3& point, const Vec3& normal, double window);

  /// Counts the particles that changed side since the last update, at time t [s].
  void update(const ParticleSystem& ps, double t);
  double mass() const { return mass_; }  ///< net mass crossed along the normal [kg]
  double rate() const;                   ///< over the window [kg/s]

  void save(io::BinaryWriter& out) const;
  void load(io::BinaryReader& in);

 private:
  Vec3 point_, normal_;
  double window_;
  double mass_ = 0.0;
  std::vector<std::int8_t> side_;  // by body id: +1 on the normal's side, -1 behind, 0 unseen
  SampleWindow samples_;           // (time, mass) over the last window
};

}  // namespace bushel
