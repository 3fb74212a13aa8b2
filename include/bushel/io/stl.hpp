#pragma once
// STL triangle surfaces (binary and ASCII) in and out. Reading welds the corners that STL
// repeats for every triangle into shared vertices and drops degenerate triangles, so that a
// mesh read from a CAD export is ready for contact detection.

#include <cstddef>
#include <string>
#include <string_view>

#include "bushel/core/triangle_mesh.hpp"

namespace bushel::io {

/// What reading an STL file found, for logs and for warnings about poor exports.
struct StlReport {
  std::size_t triangles_read = 0;      ///< facets in the file (before dropping degenerate ones)
  std::size_t degenerate_dropped = 0;  ///< facets dropped: zero area or two corners welded together
  std::size_t vertices = 0;            ///< distinct vertices after welding
};

/// Parses the content of an STL file; `source` names it in errors. A file whose size is
/// exactly 84 + 50 n bytes, n being the little-endian uint32 at byte 80, is binary (even if
/// its header starts with "solid"); otherwise it is ASCII (solid / facet normal / outer loop /
/// vertex x y z / endloop / endfacet / endsolid, keywords in any case, several solids allowed).
/// Coordinates are multiplied by `scale` (e.g. 0.001 for a file in millimetres) to give metres.
/// Corners that are bit-identical after scaling become one vertex (-0 counts as +0); vertices
/// are numbered in order of first appearance. Triangles with zero area (up to rounding) are
/// dropped and counted in `report` if given. Throws InputError with the source and, for ASCII,
/// the line: malformed syntax, non-finite coordinates, a truncated binary file, a scale that is
/// not positive and finite (key "scale"), no triangles left.
TriangleMesh parse_stl(std::string_view bytes, const std::string& source, double scale = 1.0,
                       StlReport* report = nullptr);

/// Reads and parses an STL file (see parse_stl); throws InputError if it cannot be read.
TriangleMesh read_stl(const std::string& path, double scale = 1.0, StlReport* report = nullptr);

/// The bytes of an STL file for `mesh` (coordinates in metres, as stored): binary
/// (little-endian float32, unit facet normals from the corner order, attribute 0) or ASCII
/// (shortest round-trip decimals). `name` goes into the header or the solid line. Throws
/// std::invalid_argument if a triangle indexes a missing vertex or the mesh is too large for
/// binary STL.
std::string stl_bytes(const TriangleMesh& mesh, bool binary, const std::string& name);

/// Writes stl_bytes(mesh, binary, name) to `path` atomically; throws InputError if it fails.
void write_stl(const std::string& path, const TriangleMesh& mesh, bool binary = true,
               const std::string& name = "bushel");

}  // namespace bushel::io
