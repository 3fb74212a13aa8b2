#pragma once
// VTK XML output for ParaView: unstructured grids (.vtu) for surfaces, particles and contact
// lines, and collections (.pvd) that put the frames of a run on a time axis. Two encodings:
// ASCII (diffable, readable without VTK) and binary (raw appended data compressed by zlib in
// blocks, as VTK's own vtkZLibDataCompressor writes it: several times smaller and faster to
// read). Either way every value reads back exactly.

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bushel/core/triangle_mesh.hpp"
#include "bushel/core/vec3.hpp"

namespace bushel::io {

/// The type an array is stored as. Integer types hold ids, counts and indices: their values
/// must be whole numbers in range.
enum class VtuType { float64, int32, uint32 };

/// A named field over the points or the cells of a piece.
struct VtuArray {
  std::string name;                 ///< shown in ParaView; include the unit, e.g. "velocity_m_s"
  int components = 1;               ///< 1 for a scalar, 3 for a vector, 9 for a tensor
  std::vector<double> values;       ///< SI values, interleaved: components x (points or cells)
  VtuType type = VtuType::float64;  ///< how they are stored
};

/// A named list of words in the piece's field data (e.g. the particle types' names, indexed
/// by the `type` point array).
struct VtuStrings {
  std::string name;
  std::vector<std::string> values;  ///< printable text without NUL characters
};

/// One unstructured grid: points, cells given VTK style, and fields.
struct VtuPiece {
  std::vector<Vec3> points;                 ///< [m]
  std::vector<std::uint32_t> connectivity;  ///< point indices of all cells, one cell after another
  std::vector<std::uint32_t> offsets;       ///< per cell, the END of its indices in `connectivity`
  std::vector<std::uint8_t> types;          ///< per cell, the VTK cell type (kVtkVertex, kVtkTriangle, ...)
  std::vector<VtuArray> point_data;         ///< one value tuple per point
  std::vector<VtuArray> cell_data;          ///< one value tuple per cell
  std::vector<VtuStrings> field_strings;    ///< field data over the whole piece
};

/// How a file stores its arrays.
enum class VtuEncoding {
  ascii,  ///< numbers as text in the XML
  zlib,   ///< raw binary appended after the XML, zlib-compressed in blocks of 32 KiB
};

inline constexpr std::uint8_t kVtkVertex = 1;    ///< VTK_VERTEX: one point
inline constexpr std::uint8_t kVtkLine = 3;      ///< VTK_LINE: two points
inline constexpr std::uint8_t kVtkTriangle = 5;  ///< VTK_TRIANGLE: three points, counter-clockwise

/// The XML of a .vtu file holding `piece`. Throws std::invalid_argument naming what does not
/// fit: offsets and types of different lengths, offsets not increasing or not ending at the
/// connectivity's size, an index beyond the points, an array whose size is not components x
/// count, an unnamed array, a non-finite value (ParaView cannot read those back), a value of
/// an integer array that is not a whole number in the type's range, a string with a NUL.
std::string vtu_text(const VtuPiece& piece);

/// The bytes of a .vtu file holding `piece` in `encoding` (vtu_text for ascii); the same checks.
std::string vtu_file(const VtuPiece& piece, VtuEncoding encoding);

/// Writes vtu_file(piece, encoding) to `path` atomically; throws InputError if the file cannot
/// be written.
void write_vtu(const std::string& path, const VtuPiece& piece, VtuEncoding encoding = VtuEncoding::ascii);

/// A surface: the mesh's vertices as points, its triangles as VTK_TRIANGLE cells (in order, so
/// cell data follows the triangle index). Throws std::invalid_argument for an index beyond the
/// vertices.
VtuPiece surface_piece(const TriangleMesh& mesh);

/// Particles or probes: one VTK_VERTEX cell per point, so that ParaView shows them as points
/// (glyph them with a radius array in point_data).
VtuPiece point_cloud_piece(std::span<const Vec3> points);

/// Writes a ParaView collection (.pvd) listing `time_and_file`: simulation time [s] and the
/// file of that frame, relative to the .pvd's directory. Atomic; throws std::invalid_argument
/// for a non-finite time, InputError if the file cannot be written.
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& time_and_file);

}  // namespace bushel::io
