// Geometry data structures against brute force: the nearest point of every face kind against
// a dense sampling of the face, the face grid against testing every face, and the merging of
// a part's contacts (one contact per touch, one per wall in a corner).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "bushel/core/input_error.hpp"
#include "bushel/core/quat.hpp"
#include "bushel/geometry/face_grid.hpp"
#include "bushel/geometry/motion.hpp"
#include "bushel/geometry/part_contact.hpp"
#include "bushel/geometry/shapes.hpp"
#include "bushel/integrate/simulation.hpp"

using namespace bushel;

namespace {

constexpr double pi = std::numbers::pi;

// Points spread over a face (its closure), for brute-force distances.
std::vector<Vec3> sample(const Face& f, int n) {
  std::vector<Vec3> pts;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
      switch (f.kind) {
        case FaceKind::triangle:
          if (u + v <= 1.0) pts.push_back(f.a + u * (f.b - f.a) + v * (f.c - f.a));
          break;
        case FaceKind::rectangle:
          pts.push_back(f.a + (2 * u - 1) * f.b + (2 * v - 1) * f.c);
          break;
        case FaceKind::revolved: {
          const double rho = f.a.x + u * (f.b.x - f.a.x), z = f.a.y + u * (f.b.y - f.a.y);
          for (int k = 0; k < 4 * n; ++k) {
            const double phi = 2 * pi * k / (4 * n);
            pts.push_back({rho * std::cos(phi), rho * std::sin(phi), z});
          }
          break;
        }
        case FaceKind::half_space:
          break;
      }
    }
  }
  return pts;
}

void expect_nearest_matches_sampling(const Face& f, double spacing, std::uint64_t seed) {
  const std::vector<Vec3> pts = sample(f, 40);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> c(-0.06, 0.06);
  for (int k = 0; k < 150; ++k) {
    const Vec3 p{c(rng), c(rng), c(rng)};
    double brute = INFINITY;
    for (const Vec3& q : pts) brute = std::min(brute, norm(p - q));
    const FacePoint fp = nearest(f, p);
    EXPECT_NEAR(fp.distance, norm(p - fp.point), 1e-12);
    EXPECT_LE(fp.distance, brute + 1e-12) << "nearest() is not the nearest point";
    EXPECT_GE(fp.distance, brute - spacing) << "nearest() is closer than the face";
  }
}

std::vector<std::uint32_t> all(const std::vector<Face>& faces) {
  std::vector<std::uint32_t> c(faces.size());
  for (std::size_t i = 0; i < c.size(); ++i) c[i] = static_cast<std::uint32_t>(i);
  return c;
}

}  // namespace

TEST(Geometry, NearestPointOfEveryFaceKind) {
  expect_nearest_matches_sampling(triangle_face({0.01, -0.02, 0.0}, {0.03, 0.01, 0.02}, {-0.02, 0.02, -0.01}), 2e-3, 1);
  expect_nearest_matches_sampling(rectangle_face({0.0, 0.01, 0.0}, {0.02, 0.0, 0.01}, {0.0, 0.03, 0.0}), 2e-3, 2);
  expect_nearest_matches_sampling(revolved_face(0.03, -0.02, 0.03, 0.02), 3e-3, 3);  // cylinder band
  expect_nearest_matches_sampling(revolved_face(0.01, -0.02, 0.04, 0.03), 3e-3, 4);  // cone band
  expect_nearest_matches_sampling(revolved_face(0.04, 0.0, 0.0, 0.0), 3e-3, 5);      // full disc
  expect_nearest_matches_sampling(revolved_face(0.04, 0.01, 0.015, 0.01), 3e-3, 6);  // annulus
}

TEST(Geometry, RimAndSideFlags) {
  const Face band = revolved_face(0.05, 0.0, 0.05, 0.1, inside);
  const FacePoint in = nearest(band, {0.01, 0.0, 0.05});
  EXPECT_FALSE(in.on_rim);
  EXPECT_FALSE(in.front_side);  // inside a band whose front points outwards
  EXPECT_NEAR(in.distance, 0.04, 1e-15);
  EXPECT_TRUE(nearest(band, {0.06, 0.0, 0.12}).on_rim);
  EXPECT_FALSE(side_allows(band, true));
  const Face disc = revolved_face(0.04, 0.0, 0.0, 0.0);
  EXPECT_FALSE(nearest(disc, {0.0, 0.0, 0.01}).on_rim);  // the centre of a disc is no rim
  EXPECT_TRUE(nearest(disc, {0.0, 0.0, 0.01}).front_side);
  EXPECT_NEAR(surface_offset(revolved_face(0.01, 0.0, 0.02, 0.01), {0.02, 0.0, 0.0}), std::sqrt(0.5) * 0.01, 1e-15);
}

TEST(Geometry, FaceGridFindsEveryNearbyFace) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> c(-0.05, 0.05), s(-0.004, 0.004);
  std::vector<Face> faces;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 a{c(rng), c(rng), c(rng)};
    faces.push_back(triangle_face(a, a + Vec3{s(rng), s(rng), s(rng)}, a + Vec3{s(rng), s(rng), s(rng)}));
  }
  // Two large panels among the small triangles: they span far more cells than the rest.
  faces.push_back(rectangle_face({0, 0, 0.01}, {0.05, 0, 0.02}, {0, 0.05, 0}));
  faces.push_back(triangle_face({-0.05, -0.05, -0.05}, {0.05, 0.05, 0.05}, {0.05, -0.05, 0.0}));
  const FaceGrid grid(faces);
  EXPECT_GT(grid.cells(), 100u);
  std::vector<std::uint32_t> found;
  for (int k = 0; k < 500; ++k) {
    const Vec3 p{1.2 * c(rng), 1.2 * c(rng), 1.2 * c(rng)};
    const double reach = 0.002 + 0.004 * (k % 3);
    found.clear();
    grid.query(p, reach, found);
    EXPECT_TRUE(std::is_sorted(found.begin(), found.end()));
    EXPECT_EQ(std::adjacent_find(found.begin(), found.end()), found.end());
    for (std::uint32_t f = 0; f < faces.size(); ++f) {
      if (nearest(faces[f], p).distance < reach) {
        EXPECT_TRUE(std::binary_search(found.begin(), found.end(), f)) << "face " << f << " missed";
      }
    }
  }
}

TEST(Geometry, OneContactOnAFlatMeshWhereverTheSphereSits) {
  const std::vector<Face> faces = faces_of(MeshSpec{square_mesh(0.06, 6), "flat"});
  const std::vector<std::uint32_t> cand = all(faces);
  const double r = 2e-3, overlap = 2e-5;
  std::array<PartTouch, max_part_touches> t;
  // Over a face, on an edge (between two triangles, diagonal or not) and on a vertex of six.
  for (const Vec3& xy : {Vec3{0.0031, 0.0012, 0}, Vec3{0.005, 0.002, 0}, Vec3{0.002, 0.002, 0}, Vec3{0.0, 0.0, 0},
                         Vec3{0.01, -0.01, 0}}) {
    const int n = part_touches(faces, cand, xy + Vec3{0, 0, r - overlap}, r, t);
    ASSERT_EQ(n, 1) << "at " << xy.x << " " << xy.y;
    EXPECT_NEAR(t[0].overlap, overlap, 1e-15);
    EXPECT_NEAR(t[0].normal.z, -1.0, 1e-12);
  }
  // Random positions over the mesh, deeper contacts too.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.02, 0.02), d(1e-6, 2e-4);
  for (int k = 0; k < 2000; ++k) {
    const double o = d(rng);
    ASSERT_EQ(part_touches(faces, cand, {u(rng), u(rng), r - o}, r, t), 1);
    EXPECT_NEAR(t[0].overlap, o, 1e-12);
  }
}

TEST(Geometry, ConvexMeshEdgeGivesOneContact) {
  // Two triangles folded 90 degrees along the x axis (a ridge): a sphere over the ridge.
  const std::vector<Face> faces{triangle_face({-0.01, 0, 0}, {0.01, 0, 0}, {0, -0.01, -0.01}),
                                triangle_face({0.01, 0, 0}, {-0.01, 0, 0}, {0, 0.01, -0.01})};
  std::array<PartTouch, max_part_touches> t;
  const double r = 2e-3;
  ASSERT_EQ(part_touches(faces, all(faces), {0.001, 0, r - 1e-5}, r, t), 1);
  EXPECT_NEAR(t[0].overlap, 1e-5, 1e-15);
}

TEST(Geometry, CornerOfABoxGivesOneContactPerWall) {
  const std::vector<Face> faces = faces_of(BoxSpec{{0.02, 0.02, 0.02}, inside});
  std::array<PartTouch, max_part_touches> t;
  const double r = 2e-3, o = 1e-5;
  const Vec3 corner{0.01 - r + o, 0.01 - r + 2 * o, -0.01 + r - 3 * o};
  ASSERT_EQ(part_touches(faces, all(faces), corner, r, t), 3);
  EXPECT_NEAR(t[0].overlap, 3 * o, 1e-15);  // deepest first
  EXPECT_NEAR(t[1].overlap, 2 * o, 1e-15);
  EXPECT_NEAR(t[2].overlap, o, 1e-15);
  // From outside, an inside-only box does not touch.
  EXPECT_EQ(part_touches(faces, all(faces), {0.01 + r - o, 0, 0}, r, t), 0);
}

TEST(Geometry, FacetedConcaveWallActsAsOneSurface) {
  // The inside of a 48-gon (a tessellated cup wall): a sphere at a vertex between two facets
  // touches both, 7.5 degrees apart; it is one touch, not two.
  TriangleMesh m;
  const int n = 48;
  const double R = 0.045;
  for (int k = 0; k < n; ++k) {
    const double phi = 2 * pi * k / n;
    m.vertices.push_back({R * std::cos(phi), R * std::sin(phi), 0.0});
    m.vertices.push_back({R * std::cos(phi), R * std::sin(phi), 0.05});
  }
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t a = 2 * k, b = 2 * ((k + 1) % n);
    m.triangles.push_back({a, b, b + 1});
    m.triangles.push_back({a, b + 1, a + 1});
  }
  const std::vector<Face> faces = faces_of(MeshSpec{m, "cup"});
  std::array<PartTouch, max_part_touches> t;
  const double r = 2e-3;
  const Vec3 p{R - r + 1e-5, 0.0, 0.02};  // at the vertex line phi = 0
  EXPECT_EQ(part_touches(faces, all(faces), p, r, t), 1);
}

TEST(Geometry, PrimitivesValidateTheirSizes) {
  EXPECT_THROW(faces_of(CylinderSpec{-0.01, 0.1}), InputError);
  EXPECT_THROW(faces_of(DiscSpec{0.01, 0.02}), InputError);
  EXPECT_THROW(faces_of(MeshSpec{}), InputError);
  EXPECT_THROW(ConeSpec::funnel(0.05, 0.06, 1.0), InputError);
  const ConeSpec f = ConeSpec::funnel(0.1, 0.02, pi / 3);
  EXPECT_NEAR(f.height, 0.04 * std::tan(pi / 3), 1e-15);
  EXPECT_EQ(faces_of(CylinderSpec{0.05, 0.1, inside, true, false}).size(), 2u);
  EXPECT_EQ(faces_of(BoxSpec{{0.1, 0.1, 0.1}}).size(), 6u);
}

TEST(Geometry, TessellatedFacesFaceOutwards) {
  // Each display triangle's normal agrees with the face's front.
  for (const Face& f : faces_of(CylinderSpec{0.05, 0.1, Side::both, true, true})) {
    const TriangleMesh m = tessellate({f}, 32);
    for (std::size_t k = 0; k < m.size(); ++k) {
      const Vec3 a = m.corner(k, 0), b = m.corner(k, 1), c = m.corner(k, 2);
      const Vec3 centre = (a + b + c) / 3.0, normal = cross(b - a, c - a);
      EXPECT_TRUE(nearest(f, centre + 1e-3 * normalized(normal)).front_side);  // beyond the chords' sag
    }
  }
}

TEST(Motion, TurnIsExactWhateverTheStep) {
  Motion m;
  m.segments.push_back(MotionSegment::turn({1, 0, 0}, {0, 0.01, 0}, pi, 7.85, 0.6));
  m.validate();
  Pose pose{{0, 0.03, 0}, {}};
  const double dt = 3.7e-5;
  double t = 0.0;
  while (t < 1.2) {
    advance(m, 0.0, pose, t, dt, 0.05);
    t += dt;
  }
  // Turned by exactly pi about the x axis through (0, 0.01, 0).
  EXPECT_NEAR(pose.position.y, -0.01, 1e-12);
  EXPECT_NEAR(std::abs(pose.orientation.x), 1.0, 1e-12);
  EXPECT_NEAR(m.segments[0].end - m.segments[0].start, pi / 7.85, 1e-15);
}

TEST(Motion, TapLiftsThenDropsInFreeFall) {
  MotionSegment s;
  s.kind = MotionSegment::Kind::tap;
  s.amplitude = 3e-3;
  s.frequency = 4.33;
  const double period = 1 / 4.33, fall = std::sqrt(2 * 3e-3 / 9.81);
  EXPECT_NEAR(s.offset(0.0), 0.0, 1e-15);
  EXPECT_NEAR(s.offset(period - fall), 3e-3, 1e-12);                             // top of the lift
  EXPECT_NEAR(s.offset_rate(period - 1e-9), -std::sqrt(2 * 9.81 * 3e-3), 1e-6);  // impact speed
  EXPECT_NEAR(s.offset(period + 1e-9), 0.0, 1e-9);
  Motion bad;
  s.frequency = 50;  // no time to fall 3 mm (24.7 ms) in a 20 ms period
  bad.segments.push_back(s);
  EXPECT_THROW(bad.validate(), InputError);
}

TEST(Motion, ServoMovesTowardsItsTarget) {
  ServoSpec s;
  s.axis = {0, 0, -1};
  s.target_force = 10.0;
  s.gain = 1e-3;
  s.max_speed = 5e-3;
  ServoState st = update_servo(s, {}, {0, 0, 2.0}, {}, 0.0);  // particles push up with 2 N
  EXPECT_NEAR(st.speed, 8e-3 > 5e-3 ? 5e-3 : 8e-3, 1e-15);
  EXPECT_FALSE(st.held);
  st = update_servo(s, st, {0, 0, 10.05}, {}, 0.1);
  EXPECT_TRUE(st.held);
  EXPECT_NEAR(st.speed, -5e-5, 1e-15);
  st = update_servo(s, st, {0, 0, 9.95}, {}, 0.2);
  EXPECT_TRUE(st.held);
  EXPECT_EQ(st.held_since, 0.1);
}

TEST(Motion, ServoStopsAtItsLimitAndRidesUpUnderLoad) {
  // A striker pressed down with 2 N, its origin no lower than z = 0.1 m (limit = -0.1 along
  // the downward axis), while it also moves along y.
  Motion m;
  MotionSegment across;
  across.velocity = {0, 0.2, 0};
  m.segments.push_back(across);
  m.has_servo = true;
  m.servo.axis = {0, 0, -1};
  m.servo.target_force = 2.0;
  m.servo.gain = 0.1;
  m.servo.max_speed = 0.5;
  m.servo.limit = -0.1;
  m.validate();
  Pose pose{{0, 0, 0.1005}, {}};
  // nothing under it: it moves down at full speed, 0.5 mm of which are left, and stops there
  ServoState st = update_servo(m.servo, {}, {}, pose.position, 0.0);
  EXPECT_EQ(st.speed, 0.2);  // (gain x 2 N)
  const double moved = advance(m, st.speed, pose, 0.0, 0.01, 0.0);
  EXPECT_NEAR(pose.position.z, 0.1, 1e-15);
  EXPECT_NEAR(pose.position.y, 0.002, 1e-15);
  EXPECT_NEAR(moved, 0.002 + 0.0005, 1e-15);
  st = update_servo(m.servo, st, {}, pose.position, 0.01);
  EXPECT_EQ(st.speed, 0.0);  // at its limit
  EXPECT_EQ(twist_at(m, st.speed, pose, 0.01).velocity.z, 0.0);
  // a kernel caught under it pushes up with 5 N: it rises at gain x 3 N
  st = update_servo(m.servo, st, {0, 0, 5.0}, pose.position, 0.02);
  EXPECT_NEAR(st.speed, -0.3, 1e-15);
  advance(m, st.speed, pose, 0.02, 0.001, 0.0);
  EXPECT_NEAR(pose.position.z, 0.1003, 1e-15);
  m.servo.limit = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(m.validate(), InputError);
}

TEST(Parts, BadPartsAreInputErrors) {
  SimulationSettings s;
  s.dt = 1e-5;
  Simulation sim(s);
  const Material steel = materials::steel();
  EXPECT_THROW(plane_part("floor", steel, {0, 0, 0}, {0, 0, 0}), InputError);  // no normal
  EXPECT_THROW(sim.add_part(make_part("lid", DiscSpec{0.02}, steel, {{0, 0, NAN}, {}})), InputError);
  EXPECT_THROW(sim.add_part(make_part("lid", DiscSpec{0.02}, steel, {{}, {0, 0, 0, 0}})), InputError);
  MeshSpec broken{square_mesh(0.01, 1), "in code"};
  broken.mesh.triangles[1][2] = 9;
  EXPECT_THROW(sim.add_part(make_part("mesh", broken, steel)), InputError);
  try {
    sim.add_part(make_part("cup", CylinderSpec{0.03, -0.1}, steel));
    FAIL() << "a negative height was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "parts.cup.height");
  }
  const std::size_t floor = sim.add_part(plane_part("floor", steel, {0, 0, 0}, {0, 0, 1}));
  Motion spin;
  spin.segments.push_back(MotionSegment::turn({1, 0, 0}, {}, 1.0, 1.0, 0.0));
  EXPECT_THROW(sim.set_motion(floor, spin), InputError);                                     // a plane cannot rotate
  EXPECT_THROW(sim.add_part(plane_part("floor", steel, {0, 0, 1}, {0, 0, 1})), InputError);  // name taken
  EXPECT_EQ(sim.part_index("floor"), floor);
  EXPECT_THROW(sim.part_index("flor"), InputError);
}

TEST(Parts, VelocityVerletTakesParticlesAddedBetweenSteps) {
  // New particles after forces were computed: the arrays grow and the forces are recomputed
  // before the first half kick (under ASan this would catch a write past an array's end).
  SimulationSettings s;
  s.dt = 2e-6;
  s.integrator = Integrator::velocity_verlet;
  s.contacts = ContactTable({0.5, 0.3, 0.0});
  Simulation sim(s);
  sim.add_part(plane_part("floor", materials::steel(), {0, 0, 0}, {0, 0, 1}));
  const auto t = sim.add_type({"grain", make_template("sphere", {{{0, 0, 0}, 1e-3}}), materials::wheat()});
  sim.add_body(t, {{0, 0, 0.9999e-3}, {}, {}, {}});
  sim.step(10);
  for (int k = 1; k <= 20; ++k) sim.add_body(t, {{0.003 * k, 0, 0.9999e-3}, {}, {}, {}});
  sim.step(10);
  EXPECT_EQ(sim.part(0).touches, 21u);
  EXPECT_GT(-sim.part(0).force.z, 0.0);
}
