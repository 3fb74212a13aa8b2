#include "bushel/geometry/shapes.hpp"

#include <cmath>
#include <numbers>

#include "bushel/core/input_error.hpp"

namespace bushel {
namespace {

void require_size(double v, const char* key, bool zero_ok = false) {
  if (!std::isfinite(v) || v < 0.0 || (!zero_ok && v == 0.0)) {
    throw InputError(std::string("expected a ") + (zero_ok ? "non-negative" : "positive") +
                     " finite length in metres, got " + std::to_string(v))
        .with_key(key);
  }
}

// Caps of a closed solid of revolution: their fronts point into the solid, so a cap touched
// from the solid's inside is touched from its front.
Side cap_side(Side solid) { return solid == Side::both ? Side::both : (solid == inside ? Side::front : Side::back); }

void revolved_solid(std::vector<Face>& f, double r0, double r1, double h, Side side, bool bottom, bool top) {
  f.push_back(revolved_face(r0, 0.0, r1, h, side));  // front outwards (segment turned by -90 degrees)
  if (bottom && r0 > 0.0) f.push_back(revolved_face(r0, 0.0, 0.0, 0.0, cap_side(side)));  // front +z
  if (top && r1 > 0.0) f.push_back(revolved_face(0.0, h, r1, h, cap_side(side)));         // front -z
}

}  // namespace

ConeSpec ConeSpec::funnel(double top_diameter, double outlet_diameter, double wall_angle) {
  require_size(top_diameter, "top_diameter");
  require_size(outlet_diameter, "outlet_diameter", true);
  if (!(wall_angle > 0.0 && wall_angle < 0.5 * std::numbers::pi)) {
    throw InputError("expected a wall angle between 0 and 90 degrees from the horizontal").with_key("wall_angle");
  }
  if (!(outlet_diameter < top_diameter)) {
    throw InputError("expected the outlet diameter below the top diameter").with_key("outlet_diameter");
  }
  ConeSpec c;
  c.bottom_radius = 0.5 * outlet_diameter;
  c.top_radius = 0.5 * top_diameter;
  c.height = (c.top_radius - c.bottom_radius) * std::tan(wall_angle);
  c.side = inside;
  return c;
}

std::vector<Face> faces_of(const ShapeSpec& shape) {
  std::vector<Face> f;
  struct Visitor {
    std::vector<Face>& f;
    void operator()(const PlaneSpec&) const { f.push_back(half_space_face()); }
    void operator()(const DiscSpec& d) const {
      require_size(d.radius, "radius");
      require_size(d.inner_radius, "inner_radius", true);
      if (!(d.inner_radius < d.radius)) throw InputError("expected inner_radius < radius").with_key("inner_radius");
      f.push_back(revolved_face(d.radius, 0.0, d.inner_radius, 0.0));
    }
    void operator()(const CylinderSpec& c) const {
      require_size(c.radius, "radius");
      require_size(c.height, "height");
      revolved_solid(f, c.radius, c.radius, c.height, c.side, c.cap_bottom, c.cap_top);
    }
    void operator()(const ConeSpec& c) const {
      require_size(c.bottom_radius, "bottom_radius", true);
      require_size(c.top_radius, "top_radius", true);
      require_size(c.height, "height");
      if (c.bottom_radius == 0.0 && c.top_radius == 0.0) {
        throw InputError("expected a positive radius at one end at least").with_key("top_radius");
      }
      revolved_solid(f, c.bottom_radius, c.top_radius, c.height, c.side, c.cap_bottom, c.cap_top);
    }
    void operator()(const BoxSpec& b) const {
      require_size(b.size.x, "size.x");
      require_size(b.size.y, "size.y");
      require_size(b.size.z, "size.z");
      const Vec3 h = 0.5 * b.size;
      const Vec3 ex{h.x, 0, 0}, ey{0, h.y, 0}, ez{0, 0, h.z};
      // Fronts outwards: u x v along the outward normal.
      f.push_back(rectangle_face(ex, ey, ez, b.side));
      f.push_back(rectangle_face(-1.0 * ex, ez, ey, b.side));
      f.push_back(rectangle_face(ey, ez, ex, b.side));
      f.push_back(rectangle_face(-1.0 * ey, ex, ez, b.side));
      f.push_back(rectangle_face(ez, ex, ey, b.side));
      f.push_back(rectangle_face(-1.0 * ez, ey, ex, b.side));
    }
    void operator()(const PlateSpec& p) const {
      require_size(p.length, "length");
      require_size(p.width, "width");
      f.push_back(rectangle_face({}, {0.5 * p.length, 0, 0}, {0, 0.5 * p.width, 0}));
    }
    void operator()(const MeshSpec& m) const {
      if (m.mesh.size() == 0) throw InputError("expected a mesh with at least one triangle").at(m.source);
      for (const Vec3& v : m.mesh.vertices) {
        if (!std::isfinite(norm(v))) throw InputError("expected finite vertex coordinates in m").at(m.source);
      }
      for (const auto& t : m.mesh.triangles) {
        for (const std::uint32_t i : t) {
          if (i >= m.mesh.vertices.size()) {
            throw InputError("a triangle refers to vertex " + std::to_string(i) + " of " +
                             std::to_string(m.mesh.vertices.size()))
                .at(m.source);
          }
        }
      }
      for (std::size_t t = 0; t < m.mesh.size(); ++t) {
        f.push_back(triangle_face(m.mesh.corner(t, 0), m.mesh.corner(t, 1), m.mesh.corner(t, 2)));
      }
    }
  };
  std::visit(Visitor{f}, shape);
  return f;
}

std::string kind_name(const ShapeSpec& shape) {
  static const char* names[] = {"plane", "disc", "cylinder", "cone", "box", "plate", "mesh"};
  return names[shape.index()];
}

TriangleMesh square_mesh(double size, int n) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) m.vertices.push_back({size * i / n - 0.5 * size, size * j / n - 0.5 * size, 0.0});
  }
  const auto row = static_cast<std::uint32_t>(n + 1);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const auto v = static_cast<std::uint32_t>(j) * row + static_cast<std::uint32_t>(i);
      m.triangles.push_back({v, v + 1, v + row + 1});
      m.triangles.push_back({v, v + row + 1, v + row});
    }
  }
  return m;
}

TriangleMesh tessellate(const std::vector<Face>& faces, int segments, double plane_half_size) {
  TriangleMesh m;
  auto add = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
    const auto i = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {a, b, c});
    m.triangles.push_back({i, i + 1, i + 2});
  };
  for (const Face& f : faces) {
    switch (f.kind) {
      case FaceKind::triangle:
        add(f.a, f.b, f.c);
        break;
      case FaceKind::rectangle:
        add(f.a - f.b - f.c, f.a + f.b - f.c, f.a + f.b + f.c);
        add(f.a - f.b - f.c, f.a + f.b + f.c, f.a - f.b + f.c);
        break;
      case FaceKind::half_space: {
        const double s = plane_half_size;
        add({-s, -s, 0}, {s, -s, 0}, {s, s, 0});
        add({-s, -s, 0}, {s, s, 0}, {-s, s, 0});
        break;
      }
      case FaceKind::revolved:
        for (int k = 0; k < segments; ++k) {
          const double p0 = 2.0 * std::numbers::pi * k / segments, p1 = 2.0 * std::numbers::pi * (k + 1) / segments;
          auto point = [&](const Vec3& rz, double phi) {
            return Vec3{rz.x * std::cos(phi), rz.x * std::sin(phi), rz.y};
          };
          // Counter-clockwise seen from the front (outwards for a band).
          const Vec3 a0 = point(f.a, p0), a1 = point(f.a, p1), b0 = point(f.b, p0), b1 = point(f.b, p1);
          if (f.a.x > 0.0) add(a0, a1, b1);
          if (f.b.x > 0.0) add(a0, b1, b0);
        }
        break;
    }
  }
  return m;
}

}  // namespace bushel
