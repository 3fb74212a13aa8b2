#include "bushel/scenario/frame_writer.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "bushel/core/input_error.hpp"
#include "bushel/io/binary_archive.hpp"
#include "bushel/io/vtu.hpp"

namespace bushel::io {

FrameWriter::FrameWriter(std::string directory) : directory_(std::move(directory)) {
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec) throw InputError("cannot create the output directory: " + ec.message()).at(directory_);
}

void FrameWriter::write(const Simulation& sim) {
  const ParticleSystem& ps = sim.particles();
  VtuPiece particles = point_cloud_piece(ps.sphere_position);
  VtuArray radius{"radius_m", 1, ps.radius}, velocity{"velocity_m_s", 3, {}}, body{"body_id", 1, {}};
  VtuArray type{"type", 1, {}}, orientation{"orientation_wxyz", 4, {}};  // the clump's, on each element
  velocity.values.reserve(3 * ps.spheres());
  body.values.reserve(ps.spheres());
  type.values.reserve(ps.spheres());
  orientation.values.reserve(4 * ps.spheres());
  for (std::size_t s = 0; s < ps.spheres(); ++s) {
    const std::uint32_t b = ps.owner[s];
    // The element's own velocity: the body's plus its spin about the centre of mass.
    const Vec3 v = ps.velocity[b] + cross(ps.angular_velocity[b], ps.sphere_position[s] - ps.position[b]);
    velocity.values.insert(velocity.values.end(), {v.x, v.y, v.z});
    body.values.push_back(ps.body_id[b]);
    type.values.push_back(ps.body_type[b]);
    const Quat& q = ps.orientation[b];
    orientation.values.insert(orientation.values.end(), {q.w, q.x, q.y, q.z});
  }
  particles.point_data = {std::move(radius), std::move(velocity), std::move(body), std::move(type),
                          std::move(orientation)};

  TriangleMesh all;
  VtuArray part{"part", 1, {}};
  for (std::size_t i = 0; i < sim.parts(); ++i) {
    if (!sim.part(i).enabled) continue;  // (a gate taken away, a lid not yet put on: not drawn)
    const TriangleMesh m = sim.part_surface(i);
    const auto base = static_cast<std::uint32_t>(all.vertices.size());
    all.vertices.insert(all.vertices.end(), m.vertices.begin(), m.vertices.end());
    for (const auto& t : m.triangles) {
      all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
      part.values.push_back(static_cast<double>(i));
    }
  }
  VtuPiece geometry = surface_piece(all);
  geometry.cell_data.push_back(std::move(part));

  const std::size_t k = frames_.size();
  const std::string pname = fmt::format("particles_{:05d}.vtu", k), gname = fmt::format("geometry_{:05d}.vtu", k);
  write_vtu(directory_ + "/" + pname, particles);
  write_vtu(directory_ + "/" + gname, geometry);
  frames_.emplace_back(sim.time(), pname);
  geometry_frames_.emplace_back(sim.time(), gname);
  write_pvd(directory_ + "/particles.pvd", frames_);
  write_pvd(directory_ + "/geometry.pvd", geometry_frames_);
}

void FrameWriter::save(BinaryWriter& out) const {
  out.put(static_cast<std::uint64_t>(frames_.size()));
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    out.put(frames_[k].first);
    out.put(frames_[k].second);
    out.put(geometry_frames_[k].first);
    out.put(geometry_frames_[k].second);
  }
}

void FrameWriter::load(BinaryReader& in) {
  const auto n = in.get<std::uint64_t>();
  frames_.clear();
  geometry_frames_.clear();
  for (std::uint64_t k = 0; k < n; ++k) {
    const auto t = in.get<double>();
    const auto name = in.get<std::string>();
    const auto tg = in.get<double>();
    const auto gname = in.get<std::string>();
    frames_.emplace_back(t, name);
    geometry_frames_.emplace_back(tg, gname);
  }
}

}  // namespace bushel::io
