#include "bushel/scenario/frame_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "bushel/contact/neighbor_list.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/binary_archive.hpp"

namespace bushel::io {
namespace {

// The touching pairs of sphere elements of different bodies (overlap > 0): a line between
// their centres with the overlap and the elastic Hertz normal force 4/3 E* sqrt(R*)
// overlap^(3/2) (docs/physics.md section 2; damping and the tangential force are left out:
// they depend on the step), and the contacts of each element. The candidates come from the
// engine's neighbour search run afresh over the current positions (the simulation's own list
// is left stale by factories and sinks between a check and the next step).
struct Touching {
  VtuPiece lines;
  std::vector<double> per_element;
};

Touching touching_pairs(const ParticleSystem& ps) {
  const std::size_t n = ps.spheres();
  Touching t;
  t.per_element.assign(n, 0.0);
  t.lines.points = ps.sphere_position;
  // (any positive skin serves: the pairs listed are filtered by overlap below)
  const double r_min = n > 0 ? *std::min_element(ps.radius.begin(), ps.radius.end()) : 1.0;
  NeighborList candidates(1e-3 * r_min, 0);
  candidates.build(ps.sphere_position, ps.radius, ps.owner, ps.sphere_id);
  VtuArray overlap{"overlap_m", 1, {}}, force{"normal_force_elastic_N", 1, {}};
  for (std::size_t p = 0; p < candidates.pairs(); ++p) {
    const std::uint32_t i = candidates.first(p), j = candidates.second(p);
    const double ri = ps.radius[i], rj = ps.radius[j];
    const double d = ri + rj - norm(ps.sphere_position[j] - ps.sphere_position[i]);
    if (!(d > 0.0)) continue;
    const Material& mi = ps.types()[ps.body_type[ps.owner[i]]].material;
    const Material& mj = ps.types()[ps.body_type[ps.owner[j]]].material;
    overlap.values.push_back(d);
    force.values.push_back(4.0 / 3.0 * effective_youngs_modulus(mi, mj) * std::sqrt(ri * rj / (ri + rj)) * d *
                           std::sqrt(d));
    t.lines.connectivity.insert(t.lines.connectivity.end(), {i, j});
    t.lines.offsets.push_back(static_cast<std::uint32_t>(t.lines.connectivity.size()));
    t.lines.types.push_back(kVtkLine);
    t.per_element[i] += 1.0, t.per_element[j] += 1.0;
  }
  t.lines.cell_data = {std::move(overlap), std::move(force)};
  return t;
}

VtuPiece particle_piece(const Simulation& sim, const FrameOptions& o, const Touching& touching) {
  const ParticleSystem& ps = sim.particles();
  VtuPiece particles = point_cloud_piece(ps.sphere_position);
  VtuArray radius{"radius_m", 1, ps.radius}, velocity{"velocity_m_s", 3, {}};
  VtuArray body{"body_id", 1, {}, VtuType::uint32}, type{"type", 1, {}, VtuType::int32};
  VtuArray orientation{"orientation_wxyz", 4, {}};  // the clump's, on each element
  VtuArray spin{"angular_velocity_rad_s", 3, {}}, force{"force_N", 3, {}};
  for (std::size_t s = 0; s < ps.spheres(); ++s) {
    const std::uint32_t b = ps.owner[s];
    // The element's own velocity: the body's plus its spin about the centre of mass.
    const Vec3 v = ps.velocity[b] + cross(ps.angular_velocity[b], ps.sphere_position[s] - ps.position[b]);
    velocity.values.insert(velocity.values.end(), {v.x, v.y, v.z});
    body.values.push_back(ps.body_id[b]);
    type.values.push_back(ps.body_type[b]);
    const Quat q = ps.orientation_of(b);
    orientation.values.insert(orientation.values.end(), {q.w, q.x, q.y, q.z});
    const Vec3 &w = ps.angular_velocity[b], &f = sim.body_force(b);
    if (o.angular_velocity) spin.values.insert(spin.values.end(), {w.x, w.y, w.z});
    if (o.force) force.values.insert(force.values.end(), {f.x, f.y, f.z});
  }
  particles.point_data = {std::move(radius), std::move(velocity), std::move(body), std::move(type),
                          std::move(orientation)};
  if (o.angular_velocity) particles.point_data.push_back(std::move(spin));
  if (o.force) particles.point_data.push_back(std::move(force));
  if (o.coordination) particles.point_data.push_back({"contacts", 1, touching.per_element, VtuType::int32});
  VtuStrings names{"type_names", {}};
  for (const ParticleType& t : ps.types()) names.values.push_back(t.name);
  particles.field_strings.push_back(std::move(names));
  return particles;
}

}  // namespace

FrameWriter::FrameWriter(std::string directory, FrameOptions options)
    : directory_(std::move(directory)), options_(options) {
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec) throw InputError("cannot create the output directory: " + ec.message()).at(directory_);
}

void FrameWriter::write(const Simulation& sim) {
  const std::size_t k = frames_.size();
  const std::string pname = fmt::format("particles_{:05d}.vtu", k);
  const bool need_pairs = options_.coordination || options_.contacts;
  const Touching touching = need_pairs ? touching_pairs(sim.particles()) : Touching{};
  write_vtu(directory_ + "/" + pname, particle_piece(sim, options_, touching), options_.encoding);
  if (options_.contacts) {
    const std::string cname = fmt::format("contacts_{:05d}.vtu", k);
    write_vtu(directory_ + "/" + cname, touching.lines, options_.encoding);
    std::vector<std::pair<double, std::string>> contact_frames;
    for (std::size_t f = 0; f <= k; ++f)
      contact_frames.emplace_back(f < k ? frames_[f].first : sim.time(), fmt::format("contacts_{:05d}.vtu", f));
    write_pvd(directory_ + "/contacts.pvd", contact_frames);
  }
  write_geometry(sim, k);
  frames_.emplace_back(sim.time(), pname);
  write_pvd(directory_ + "/particles.pvd", frames_);
  write_pvd(directory_ + "/geometry.pvd", geometry_frames_);
}

// The enabled parts as one surface; a file only when it differs from the last one written.
void FrameWriter::write_geometry(const Simulation& sim, std::size_t k) {
  TriangleMesh all;
  VtuArray part{"part", 1, {}, VtuType::int32};
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
  std::string bytes = vtu_file(geometry, options_.encoding);
  if (bytes != last_geometry_) {  // (nothing written yet: last_geometry_ is empty)
    const std::string gname = fmt::format("geometry_{:05d}.vtu", k);
    write_file_atomically(directory_ + "/" + gname, bytes);
    last_geometry_ = std::move(bytes);
    geometry_frames_.emplace_back(sim.time(), gname);
  } else {
    geometry_frames_.emplace_back(sim.time(), geometry_frames_.back().second);
  }
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
  last_geometry_.clear();
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
