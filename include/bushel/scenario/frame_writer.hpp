#pragma once
// Frames of a run for ParaView: at each call, the sphere elements (points with radius,
// velocity, body id, particle type and the body's orientation quaternion; the types' names in
// the field data `type_names`) go to DIR/particles_NNNNN.vtu, and the geometry parts at their
// pose (triangles with the part index) to DIR/geometry_NNNNN.vtu, written again only when
// the geometry has changed (a frame of parts at rest names the last file). On request, per
// element its body's angular velocity and force and its contact count, and a file of contact
// lines (DIR/contacts_NNNNN.vtu: a line between the centres of every two elements that touch,
// with the overlap and the elastic normal force, for force chains). particles.pvd,
// geometry.pvd (and contacts.pvd) put the frames on the time axis and are rewritten
// atomically after every frame, so an interrupted run leaves a readable set.

#include <string>
#include <utility>
#include <vector>

#include "bushel/integrate/simulation.hpp"
#include "bushel/io/archive_fwd.hpp"
#include "bushel/io/vtu.hpp"

namespace bushel::io {

/// What a frame holds beyond the positions, radii, velocities, body ids, types and
/// orientations, and how it is stored.
struct FrameOptions {
  VtuEncoding encoding = VtuEncoding::zlib;  ///< binary (zlib) or ascii
  bool angular_velocity = false;             ///< per element, its body's `angular_velocity_rad_s`
  bool force = false;  ///< per element, its body's total force of the last step, `force_N` (contacts and gravity)
  bool coordination = false;  ///< per element, `contacts`: the other elements it touches [-]
  bool contacts = false;      ///< contacts_NNNNN.vtu: the touching pairs of elements as lines
};

class FrameWriter {
 public:
  /// Creates `directory` if needed; throws InputError if it cannot.
  explicit FrameWriter(std::string directory, FrameOptions options = {});
  /// Writes the simulation's current state as the next frame.
  void write(const Simulation& sim);
  std::size_t frames() const { return frames_.size(); }
  /// The frames written so far, for a checkpoint: a restarted run goes on numbering them.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

 private:
  void write_geometry(const Simulation& sim, std::size_t k);

  std::string directory_;
  FrameOptions options_;
  std::vector<std::pair<double, std::string>> frames_, geometry_frames_;
  std::string last_geometry_;  // the bytes of the last geometry file written (not saved: a restart writes it anew)
};

}  // namespace bushel::io
