#pragma once
// The surfaces a geometry part is made of, in the part's own frame (docs/physics.md section 6).
// Four kinds cover every primitive and mesh:
//   half_space  the plane z = 0 with matter below: a floor that nothing tunnels through
//   revolved    a segment of the (rho, z) meridian plane turned about the z axis: a disc or
//               annulus (constant z), a cylinder band (constant rho) or a cone band
//   rectangle   a flat rectangle (box sides, plates)
//   triangle    one triangle of a mesh
// Every face but the half-space is a thin shell: a sphere touches it from either side unless
// the face is limited to one side (Side). The nearest point of the face to the sphere's
// centre gives the contact; whether that point lies on the face's rim (an edge or vertex
// contact) decides how contacts of one part are merged (part_contact.hpp).

#include <cstdint>

#include "bushel/core/vec3.hpp"

namespace bushel {

enum class FaceKind : std::uint8_t { half_space, revolved, rectangle, triangle };

/// Which side of a face particles may touch it from, relative to its front normal.
enum class Side : std::int8_t { back = -1, both = 0, front = 1 };

struct Face {
  FaceKind kind = FaceKind::triangle;
  Side side = Side::both;
  /// triangle: corners a, b, c (counter-clockwise seen from the front);
  /// rectangle: centre a, half-edge vectors b and c (front = b x c);
  /// revolved: meridian end points (rho, z) = (a.x, a.y) and (b.x, b.y) [m], front = the
  ///           segment direction turned by -90 degrees in the (rho, z) plane;
  /// half_space: no data (the plane z = 0, front +z).
  Vec3 a, b, c;
};

/// The nearest point of a face to a point p (a sphere's centre), in the part's frame.
struct FacePoint {
  Vec3 point;              ///< nearest point of the face [m]
  double distance = 0.0;   ///< from p to the point [m]; for a half-space the signed height of p
  bool on_rim = false;     ///< the point lies on the face's boundary (edge or vertex contact)
  bool front_side = true;  ///< p lies on the front side of the face
};

/// Nearest point of `face` to p.
FacePoint nearest(const Face& face, const Vec3& p);
/// Signed distance of q from the face's unbounded surface (its plane, cone or cylinder) [m]:
/// zero where q lies on it. Used to recognise an edge contact as part of a neighbouring face.
double surface_offset(const Face& face, const Vec3& q);
/// Whether a sphere whose centre is on the given side may touch the face.
inline bool side_allows(const Face& face, bool front_side) {
  return face.side == Side::both || (face.side == Side::front) == front_side;
}
/// Lower and upper corners of the face's bounding box (the half-space: unbounded) [m].
void bounds(const Face& face, Vec3& lo, Vec3& hi);

Face triangle_face(const Vec3& a, const Vec3& b, const Vec3& c, Side side = Side::both);
/// Rectangle with centre `centre` and orthogonal half-edge vectors u and v (front = u x v).
Face rectangle_face(const Vec3& centre, const Vec3& u, const Vec3& v, Side side = Side::both);
/// Surface of revolution of the meridian segment (rho0, z0) -> (rho1, z1) about the z axis.
Face revolved_face(double rho0, double z0, double rho1, double z1, Side side = Side::both);
Face half_space_face();

}  // namespace bushel
