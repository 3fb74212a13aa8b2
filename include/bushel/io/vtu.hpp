#pragma once
// VTK XML output for ParaView: unstructured grids (.vtu, format version 0.1, ASCII data
// arrays) for surfaces and particles, and collections (.pvd) that put the frames of a run on
// a time axis. ASCII keeps the files diffable and readable without VTK; every double is
// written so that it reads back exactly.

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bushel/core/vec3.hpp"
#include "bushel/core/triangle_mesh.hpp"

namespace bushel::io {

/// A named field over the points or the cells of a piece.
struct VtuArray {
  std::string name;            ///< shown in ParaView; include the unit, e.g. "velocity_m_s"
  int components = 1;          ///< 1 for a scalar, 3 for a vector, 9 for a tensor
  std::vector<double> values;  ///< SI values, interleaved: components x (points or cells)
};

/// One unstructured grid: points, cells given VTK style, and fields.
struct VtuPiece {
  std::vector<Vec3> points;                 ///< [m]
  std::vector<std::uint32_t> connectivity;  ///< point indices of all cells, one cell after another
  std::vector<std::uint32_t> offsets;       ///< per cell, the END of its indices in `connectivity`
  std::vector<std::uint8_t> types;          ///< per cell, the VTK cell type (kVtkVertex, kVtkTriangle, ...)
  std::vector<VtuArray> point_data;         ///< one value tuple per point
  std::vector<VtuArray> cell_data;          ///< one value tuple per cell
};

inline constexpr std::uint8_t kVtkVertex = 1;    ///< VTK_VERTEX: one point
inline constexpr std::uint8_t kVtkTriangle = 5;  ///< VTK_TRIANGLE: three points, counter-clockwise

/// The XML of a .vtu file holding `piece`. Throws std::invalid_argument naming what does not
/// fit: offsets and types of different lengths, offsets not increasing or not ending at the
/// connectivity's size, an index beyond the points, an array whose size is not components x
/// count, an unnamed array, a non-finite value (ParaView cannot read those back).
std::string vtu_text(const VtuPiece& piece);

/// Writes vtu_text(piece) to `path` atomically; throws InputError if the file cannot be written.
void write_vtu(const std::string& path, const VtuPiece& piece);

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
