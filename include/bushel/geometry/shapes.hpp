#pragma once
// The analytic primitives and meshes a geometry part can be (docs/physics.md section 6), each
// described in the part's own frame and turned into faces (face.hpp). The part's pose
// places the frame in the world. For closed shapes (cylinder, cone, box) `side` says which
// side particles touch: Side::back is the inside (the faces' fronts point outwards),
// Side::front the outside, Side::both a thin shell touched from either side.

#include <string>
#include <variant>
#include <vector>

#include "bushel/geometry/face.hpp"
#include "bushel/core/triangle_mesh.hpp"

namespace bushel {

inline constexpr Side inside = Side::back;    ///< touched from inside only (a cup, a funnel)
inline constexpr Side outside = Side::front;  ///< touched from outside only

/// Infinite plane z = 0; matter lies below it, so nothing tunnels through a floor.
struct PlaneSpec {};

/// Disc (or annulus) in z = 0 about the z axis, touched from both sides.
struct DiscSpec {
  double radius = 0.0;        ///< outer radius [m]
  double inner_radius = 0.0;  ///< 0 for a full disc [m]
};

/// Cylinder about the z axis from z = 0 to z = height.
struct CylinderSpec {
  double radius = 0.0;  ///< [m]
  double height = 0.0;  ///< [m]
  Side side = Side::both;
  bool cap_bottom = false;  ///< closed at z = 0
  bool cap_top = false;     ///< closed at z = height
};

/// Cone frustum about the z axis from z = 0 (radius bottom_radius) to z = height (radius
/// top_radius): a funnel has the larger radius on top.
struct ConeSpec {
  double bottom_radius = 0.0;  ///< [m]
  double top_radius = 0.0;     ///< [m]
  double height = 0.0;         ///< [m]
  Side side = Side::both;
  bool cap_bottom = false;
  bool cap_top = false;
  /// A funnel from its top and outlet diameters and its wall angle from the horizontal [rad].
  static ConeSpec funnel(double top_diameter, double outlet_diameter, double wall_angle);
};

/// Box centred on the origin with edges along the axes.
struct BoxSpec {
  Vec3 size;  ///< edge lengths [m]
  Side side = Side::both;
};

/// Rectangular plate in z = 0 centred on the origin, touched from both sides.
struct PlateSpec {
  double length = 0.0;  ///< along x [m]
  double width = 0.0;   ///< along y [m]
};

/// Triangle mesh (e.g. read from STL), touched from both sides.
struct MeshSpec {
  TriangleMesh mesh;   ///< vertices in the part frame [m]
  std::string source;  ///< where it came from (a file path), for messages
};

using ShapeSpec = std::variant<PlaneSpec, DiscSpec, CylinderSpec, ConeSpec, BoxSpec, PlateSpec, MeshSpec>;

/// The shape's faces; throws InputError (key = the offending field) for sizes that are not
/// positive and finite, or a mesh without triangles.
std::vector<Face> faces_of(const ShapeSpec& shape);
/// A short name of the shape's kind ("plane", "cylinder", ...).
std::string kind_name(const ShapeSpec& shape);

/// A flat square mesh in z = 0 centred on the origin: n x n cells of two triangles each, so
/// that inner vertices are shared by six triangles (tests, benchmarks).
TriangleMesh square_mesh(double size, int n);

/// Triangles approximating faces for display: curved faces with `segments` around the axis,
/// a half-space as a square of half-side `plane_half_size` [m].
TriangleMesh tessellate(const std::vector<Face>& faces, int segments = 64, double plane_half_size = 0.1);

}  // namespace bushel
