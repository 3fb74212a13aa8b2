#include "bushel/io/vtu.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>

#include "bushel/io/atomic_file.hpp"
#include "bushel/io/xml_escape.hpp"

namespace bushel::io {
namespace {

[[noreturn]] void invalid(const std::string& problem) { throw std::invalid_argument("vtu: " + problem); }

void check_array(const VtuArray& a, std::size_t count, std::string_view over) {
  if (a.name.empty()) invalid(fmt::format("a {} data array has no name", over));
  if (a.components < 1) invalid(fmt::format("array '{}' has {} components, expected at least 1", a.name, a.components));
  const std::size_t expected = static_cast<std::size_t>(a.components) * count;
  if (a.values.size() != expected) {
    invalid(fmt::format("array '{}' has {} values, expected {} components x {} {} = {}", a.name, a.values.size(),
                        a.components, count, over == "point" ? "points" : "cells", expected));
  }
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    if (!std::isfinite(a.values[i])) invalid(fmt::format("array '{}' value {} is {}", a.name, i, a.values[i]));
  }
}

void check(const VtuPiece& p) {
  for (std::size_t i = 0; i < p.points.size(); ++i) {
    const Vec3& q = p.points[i];
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
      invalid(fmt::format("point {} is not finite ({}, {}, {})", i, q.x, q.y, q.z));
    }
  }
  if (p.offsets.size() != p.types.size()) {
    invalid(
        fmt::format("{} offsets but {} cell types, expected one of each per cell", p.offsets.size(), p.types.size()));
  }
  std::uint32_t previous = 0;
  for (std::size_t c = 0; c < p.offsets.size(); ++c) {
    if (p.offsets[c] <= previous) {
      invalid(fmt::format("offset of cell {} is {}, expected more than {} (offsets are the end of each cell)", c,
                          p.offsets[c], previous));
    }
    previous = p.offsets[c];
  }
  if (previous != p.connectivity.size()) {
    invalid(fmt::format("the last offset is {} but the connectivity has {} indices", previous, p.connectivity.size()));
  }
  for (std::size_t i = 0; i < p.connectivity.size(); ++i) {
    if (p.connectivity[i] >= p.points.size()) {
      invalid(fmt::format("connectivity[{}] = {} but there are {} points", i, p.connectivity[i], p.points.size()));
    }
  }
  for (const auto& a : p.point_data) check_array(a, p.points.size(), "point");
  for (const auto& a : p.cell_data) check_array(a, p.types.size(), "cell");
}

using Out = std::back_insert_iterator<std::string>;

// Numbers six to a line keep the file readable and lines short.
template <class Range>
void write_values(Out out, const Range& values) {
  std::size_t k = 0;
  for (const auto& v : values) {
    // fmt's default for double is the shortest text that reads back to the same value.
    fmt::format_to(out, "{}{}", k % 6 == 0 ? "\n          " : " ", v);
    ++k;
  }
  fmt::format_to(out, "\n        ");
}

void write_data_array(Out out, std::string_view type, std::string_view name, int components, const auto& values) {
  fmt::format_to(out, "        <DataArray type=\"{}\"", type);
  if (!name.empty()) fmt::format_to(out, " Name=\"{}\"", xml_escaped(name));
  if (components != 1) fmt::format_to(out, " NumberOfComponents=\"{}\"", components);
  fmt::format_to(out, " format=\"ascii\">");
  write_values(out, values);
  fmt::format_to(out, "</DataArray>\n");
}

void write_field_section(Out out, std::string_view tag, const std::vector<VtuArray>& arrays) {
  if (arrays.empty()) return;
  fmt::format_to(out, "      <{}>\n", tag);
  for (const auto& a : arrays) write_data_array(out, "Float64", a.name, a.components, a.values);
  fmt::format_to(out, "      </{}>\n", tag);
}

std::uint32_t checked_count(std::size_t n, std::string_view what) {
  if (n > std::numeric_limits<std::uint32_t>::max()) invalid(fmt::format("{} {} do not fit 32-bit indices", n, what));
  return static_cast<std::uint32_t>(n);
}

}  // namespace

std::string vtu_text(const VtuPiece& p) {
  check(p);
  std::string text;
  text.reserve(64 * p.points.size() + 16 * p.connectivity.size() + 1024);
  const Out out = std::back_inserter(text);
  fmt::format_to(out,
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                 "  <UnstructuredGrid>\n"
                 "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
                 p.points.size(), p.types.size());
  write_field_section(out, "PointData", p.point_data);
  write_field_section(out, "CellData", p.cell_data);
  fmt::format_to(out, "      <Points>\n");
  std::vector<double> xyz;
  xyz.reserve(3 * p.points.size());
  for (const Vec3& q : p.points) xyz.insert(xyz.end(), {q.x, q.y, q.z});
  write_data_array(out, "Float64", "", 3, xyz);
  fmt::format_to(out, "      </Points>\n      <Cells>\n");
  // Int64 is what VTK itself writes for ids; every reader version accepts it.
  write_data_array(out, "Int64", "connectivity", 1, p.connectivity);
  write_data_array(out, "Int64", "offsets", 1, p.offsets);
  std::vector<unsigned> types(p.types.begin(), p.types.end());  // numbers, not characters
  write_data_array(out, "UInt8", "types", 1, types);
  fmt::format_to(out,
                 "      </Cells>\n"
                 "    </Piece>\n"
                 "  </UnstructuredGrid>\n"
                 "</VTKFile>\n");
  return text;
}

void write_vtu(const std::string& path, const VtuPiece& piece) { write_file_atomically(path, vtu_text(piece)); }

VtuPiece surface_piece(const TriangleMesh& mesh) {
  VtuPiece p;
  p.points = mesh.vertices;
  checked_count(3 * mesh.size(), "triangle corners");
  p.connectivity.reserve(3 * mesh.size());
  p.offsets.reserve(mesh.size());
  p.types.assign(mesh.size(), kVtkTriangle);
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    for (const std::uint32_t i : mesh.triangles[t]) {
      if (i >= mesh.vertices.size()) {
        invalid(fmt::format("triangle {} references vertex {} but the mesh has {}", t, i, mesh.vertices.size()));
      }
      p.connectivity.push_back(i);
    }
    p.offsets.push_back(static_cast<std::uint32_t>(p.connectivity.size()));
  }
  return p;
}

VtuPiece point_cloud_piece(std::span<const Vec3> points) {
  VtuPiece p;
  const std::uint32_t n = checked_count(points.size(), "points");
  p.points.assign(points.begin(), points.end());
  p.connectivity.resize(n);
  p.offsets.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    p.connectivity[i] = i;
    p.offsets[i] = i + 1;
  }
  p.types.assign(n, kVtkVertex);
  return p;
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& time_and_file) {
  std::string text =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  const Out out = std::back_inserter(text);
  for (const auto& [time, file] : time_and_file) {
    if (!std::isfinite(time))
      throw std::invalid_argument(fmt::format("pvd: time {} of '{}' is not finite", time, file));
    if (file.empty()) throw std::invalid_argument("pvd: a frame has an empty file name");
    fmt::format_to(out, "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", time, xml_escaped(file));
  }
  text += "  </Collection>\n</VTKFile>\n";
  write_file_atomically(path, text);
}

}  // namespace bushel::io
