#include "bushel/geometry/face.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bushel {
namespace {

FacePoint at(const Vec3& p, const Vec3& q, bool rim, bool front) { return {q, norm(p - q), rim, front}; }

// Ericson, Real-Time Collision Detection (2005), section 5.1.5: the Voronoi region of p
// (a vertex, an edge or the inside) decides the nearest point.
FacePoint nearest_triangle(const Face& f, const Vec3& p) {
  const Vec3 &a = f.a, &b = f.b, &c = f.c;
  const Vec3 ab = b - a, ac = c - a;
  const bool front = dot(p - a, cross(ab, ac)) >= 0.0;
  const Vec3 ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return at(p, a, true, front);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return at(p, b, true, front);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return at(p, a + (d1 / (d1 - d3)) * ab, true, front);
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return at(p, c, true, front);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return at(p, a + (d2 / (d2 - d6)) * ac, true, front);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    return at(p, b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), true, front);
  }
  const double denom = 1.0 / (va + vb + vc);
  return at(p, a + (vb * denom) * ab + (vc * denom) * ac, false, front);
}

FacePoint nearest_rectangle(const Face& f, const Vec3& p) {
  const Vec3 d = p - f.a;
  const double s = dot(d, f.b) / norm2(f.b), t = dot(d, f.c) / norm2(f.c);
  const double sc = std::clamp(s, -1.0, 1.0), tc = std::clamp(t, -1.0, 1.0);
  return at(p, f.a + sc * f.b + tc * f.c, sc != s || tc != t, dot(d, cross(f.b, f.c)) >= 0.0);
}

FacePoint nearest_revolved(const Face& f, const Vec3& p) {
  const double rho = std::sqrt(p.x * p.x + p.y * p.y);
  const double er = f.b.x - f.a.x, ez = f.b.y - f.a.y;
  const double u = ((rho - f.a.x) * er + (p.z - f.a.y) * ez) / (er * er + ez * ez);
  // An end on the axis (a full disc's centre) is no rim.
  bool rim = false;
  double uc = u;
  if (u < 0.0) uc = 0.0, rim = f.a.x > 0.0;
  if (u > 1.0) uc = 1.0, rim = f.b.x > 0.0;
  const double rc = f.a.x + uc * er, zc = f.a.y + uc * ez;
  const Vec3 q = rho > 0.0 ? Vec3{rc * p.x / rho, rc * p.y / rho, zc} : Vec3{rc, 0.0, zc};
  return at(p, q, rim, (rho - f.a.x) * ez - (p.z - f.a.y) * er >= 0.0);
}

}  // namespace

FacePoint nearest(const Face& face, const Vec3& p) {
  switch (face.kind) {
    case FaceKind::triangle:
      return nearest_triangle(face, p);
    case FaceKind::rectangle:
      return nearest_rectangle(face, p);
    case FaceKind::revolved:
      return nearest_revolved(face, p);
    case FaceKind::half_space:
      break;
  }
  return {{p.x, p.y, 0.0}, p.z, false, p.z >= 0.0};
}

double surface_offset(const Face& face, const Vec3& q) {
  switch (face.kind) {
    case FaceKind::triangle:
      return dot(q - face.a, normalized(cross(face.b - face.a, face.c - face.a)));
    case FaceKind::rectangle:
      return dot(q - face.a, normalized(cross(face.b, face.c)));
    case FaceKind::revolved: {
      const double er = face.b.x - face.a.x, ez = face.b.y - face.a.y;
      return ((std::hypot(q.x, q.y) - face.a.x) * ez - (q.z - face.a.y) * er) / std::hypot(er, ez);
    }
    case FaceKind::half_space:
      break;
  }
  return q.z;
}

void bounds(const Face& face, Vec3& lo, Vec3& hi) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  switch (face.kind) {
    case FaceKind::triangle:
      lo = min(face.a, min(face.b, face.c));
      hi = max(face.a, max(face.b, face.c));
      return;
    case FaceKind::rectangle: {
      const Vec3 e{std::abs(face.b.x) + std::abs(face.c.x), std::abs(face.b.y) + std::abs(face.c.y),
                   std::abs(face.b.z) + std::abs(face.c.z)};
      lo = face.a - e;
      hi = face.a + e;
      return;
    }
    case FaceKind::revolved: {
      const double r = std::max(face.a.x, face.b.x);
      lo = {-r, -r, std::min(face.a.y, face.b.y)};
      hi = {r, r, std::max(face.a.y, face.b.y)};
      return;
    }
    case FaceKind::half_space:
      break;
  }
  lo = {-inf, -inf, -inf};
  hi = {inf, inf, 0.0};
}

Face triangle_face(const Vec3& a, const Vec3& b, const Vec3& c, Side side) {
  return {FaceKind::triangle, side, a, b, c};
}
Face rectangle_face(const Vec3& centre, const Vec3& u, const Vec3& v, Side side) {
  return {FaceKind::rectangle, side, centre, u, v};
}
Face revolved_face(double rho0, double z0, double rho1, double z1, Side side) {
  return {FaceKind::revolved, side, {rho0, z0, 0.0}, {rho1, z1, 0.0}, {}};
}
Face half_space_face() { return {FaceKind::half_space, Side::front, {}, {}, {}}; }

}  // namespace bushel
