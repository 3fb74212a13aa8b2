#pragma once
// Frames of a run for ParaView: at each call, the sphere elements (points with radius,
// velocity, body id, particle type and the body's orientation quaternion) and the geometry
// parts at their current pose (triangles with the part index and name order of the
// simulation) go to DIR/particles_NNNNN.vtu and DIR/geometry_NNNNN.vtu; particles.pvd and
// geometry.pvd put the frames on the time axis and are rewritten (atomically) after every
// frame, so an interrupted run leaves a readable set.

#include <string>
#include <utility>
#include <vector>

#include "bushel/integrate/simulation.hpp"
#include "bushel/io/archive_fwd.hpp"

namespace bushel::io {

class FrameWriter {
 public:
  /// Creates `directory` if needed; throws InputError if it cannot.
  explicit FrameWriter(std::string directory);
  /// Writes the simulation's current state as the next frame.
  void write(const Simulation& sim);
  std::size_t frames() const { return frames_.size(); }
  /// The frames written so far, for a checkpoint: a restarted run goes on numbering them.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

 private:
  std::string directory_;
  std::vector<std::pair<double, std::string>> frames_, geometry_frames_;
};

}  // namespace bushel::io
