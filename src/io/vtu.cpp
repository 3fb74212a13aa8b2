#include "bushel/io/vtu.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
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
  const auto [lo, hi] = a.type == VtuType::int32    ? std::pair<double, double>{INT32_MIN, INT32_MAX}
                        : a.type == VtuType::uint32 ? std::pair<double, double>{0.0, UINT32_MAX}
                                                    : std::pair<double, double>{-HUGE_VAL, HUGE_VAL};
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    const double v = a.values[i];
    if (!std::isfinite(v)) invalid(fmt::format("array '{}' value {} is {}", a.name, i, v));
    if (a.type != VtuType::float64 && (v != std::trunc(v) || v < lo || v > hi)) {
      invalid(fmt::format("array '{}' value {} is {}, expected a whole number from {} to {}", a.name, i, v, lo, hi));
    }
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
  for (const auto& f : p.field_strings) {
    if (f.name.empty()) invalid("a field data string list has no name");
    for (const auto& v : f.values) {
      if (v.find('\0') != std::string::npos) invalid(fmt::format("a string of '{}' holds a NUL character", f.name));
    }
  }
}

using Out = std::back_insert_iterator<std::string>;

// The file being written: its XML, and for the binary encoding the appended data that follows.
struct FileText {
  VtuEncoding encoding;
  std::string xml, appended;
};

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

// Appends `bytes` zlib-compressed in blocks, behind VTK's header for them (UInt64 words):
// block count, block size, size of a last partial block (0 if none), each block's compressed
// size.
void append_compressed(std::string& appended, std::string_view bytes) {
  constexpr std::size_t block = 32768;
  const std::size_t blocks = (bytes.size() + block - 1) / block;
  std::vector<std::uint64_t> header{blocks, block, bytes.size() % block};
  std::string data;
  for (std::size_t k = 0; k < blocks; ++k) {
    const std::string_view part = bytes.substr(k * block, block);
    uLongf size = compressBound(static_cast<uLong>(part.size()));
    const std::size_t at = data.size();
    data.resize(at + size);
    if (compress2(reinterpret_cast<Bytef*>(data.data() + at), &size, reinterpret_cast<const Bytef*>(part.data()),
                  static_cast<uLong>(part.size()), Z_DEFAULT_COMPRESSION) != Z_OK) {
      invalid("zlib could not compress a data array");
    }
    data.resize(at + size);
    header.push_back(size);
  }
  appended.append(reinterpret_cast<const char*>(header.data()), header.size() * sizeof(std::uint64_t));
  appended += data;
}

// One DataArray: the values as text (ascii) or as bytes of T behind the XML (binary).
template <class T, class Range>
void write_data_array(FileText& f, std::string_view type, std::string_view name, int components, const Range& values) {
  const Out out = std::back_inserter(f.xml);
  fmt::format_to(out, "        <DataArray type=\"{}\"", type);
  if (!name.empty()) fmt::format_to(out, " Name=\"{}\"", xml_escaped(name));
  if (components != 1) fmt::format_to(out, " NumberOfComponents=\"{}\"", components);
  if (f.encoding == VtuEncoding::ascii) {
    fmt::format_to(out, " format=\"ascii\">");
    std::vector<T> typed;
    for (const auto& v : values) typed.push_back(static_cast<T>(v));
    if constexpr (sizeof(T) == 1) {
      write_values(out, std::vector<unsigned>(typed.begin(), typed.end()));  // numbers, not characters
    } else {
      write_values(out, typed);
    }
    fmt::format_to(out, "</DataArray>\n");
    return;
  }
  fmt::format_to(out, " format=\"appended\" offset=\"{}\"/>\n", f.appended.size());
  std::string bytes;
  for (const auto& v : values) {
    const T t = static_cast<T>(v);
    bytes.append(reinterpret_cast<const char*>(&t), sizeof(T));
  }
  append_compressed(f.appended, bytes);
}

void write_field_section(FileText& f, std::string_view tag, const std::vector<VtuArray>& arrays) {
  if (arrays.empty()) return;
  fmt::format_to(std::back_inserter(f.xml), "      <{}>\n", tag);
  for (const auto& a : arrays) {
    switch (a.type) {
      case VtuType::float64:
        write_data_array<double>(f, "Float64", a.name, a.components, a.values);
        break;
      case VtuType::int32:
        write_data_array<std::int32_t>(f, "Int32", a.name, a.components, a.values);
        break;
      case VtuType::uint32:
        write_data_array<std::uint32_t>(f, "UInt32", a.name, a.components, a.values);
        break;
    }
  }
  fmt::format_to(std::back_inserter(f.xml), "      </{}>\n", tag);
}

// Strings go as VTK writes them in ASCII: each one's character codes, then a 0.
void write_strings(FileText& f, const std::vector<VtuStrings>& lists) {
  if (lists.empty()) return;
  const Out out = std::back_inserter(f.xml);
  fmt::format_to(out, "    <FieldData>\n");
  for (const auto& l : lists) {
    fmt::format_to(out, "      <DataArray type=\"String\" Name=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">",
                   xml_escaped(l.name), l.values.size());
    std::vector<unsigned> codes;
    for (const auto& v : l.values) {
      for (const char c : v) codes.push_back(static_cast<unsigned char>(c));
      codes.push_back(0);
    }
    write_values(out, codes);
    fmt::format_to(out, "</DataArray>\n");
  }
  fmt::format_to(out, "    </FieldData>\n");
}

std::uint32_t checked_count(std::size_t n, std::string_view what) {
  if (n > std::numeric_limits<std::uint32_t>::max()) invalid(fmt::format("{} {} do not fit 32-bit indices", n, what));
  return static_cast<std::uint32_t>(n);
}

}  // namespace

std::string vtu_file(const VtuPiece& p, VtuEncoding encoding) {
  check(p);
  FileText f{encoding, {}, {}};
  f.xml.reserve(encoding == VtuEncoding::ascii ? 64 * p.points.size() + 16 * p.connectivity.size() + 1024 : 4096);
  const Out out = std::back_inserter(f.xml);
  // Binary files need format version 1.0 for their 64-bit block headers.
  if (encoding == VtuEncoding::ascii) {
    fmt::format_to(out,
                   "<?xml version=\"1.0\"?>\n"
                   "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
  } else {
    fmt::format_to(out,
                   "<?xml version=\"1.0\"?>\n"
                   "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
                   "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n");
  }
  fmt::format_to(out, "  <UnstructuredGrid>\n");
  write_strings(f, p.field_strings);
  fmt::format_to(out, "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", p.points.size(), p.types.size());
  write_field_section(f, "PointData", p.point_data);
  write_field_section(f, "CellData", p.cell_data);
  fmt::format_to(out, "      <Points>\n");
  std::vector<double> xyz;
  xyz.reserve(3 * p.points.size());
  for (const Vec3& q : p.points) xyz.insert(xyz.end(), {q.x, q.y, q.z});
  write_data_array<double>(f, "Float64", "", 3, xyz);
  fmt::format_to(out, "      </Points>\n      <Cells>\n");
  // Int64 is what VTK itself writes for ids; every reader version accepts it.
  write_data_array<std::int64_t>(f, "Int64", "connectivity", 1, p.connectivity);
  write_data_array<std::int64_t>(f, "Int64", "offsets", 1, p.offsets);
  write_data_array<std::uint8_t>(f, "UInt8", "types", 1, p.types);
  fmt::format_to(out,
                 "      </Cells>\n"
                 "    </Piece>\n"
                 "  </UnstructuredGrid>\n");
  if (encoding != VtuEncoding::ascii) {
    f.xml += "  <AppendedData encoding=\"raw\">\n   _";  // the data start after the underscore
    f.xml += f.appended;
    f.xml += "\n  </AppendedData>\n";
  }
  f.xml += "</VTKFile>\n";
  return std::move(f.xml);
}

std::string vtu_text(const VtuPiece& p) { return vtu_file(p, VtuEncoding::ascii); }

void write_vtu(const std::string& path, const VtuPiece& piece, VtuEncoding encoding) {
  write_file_atomically(path, vtu_file(piece, encoding));
}

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
