// STL reading and writing: binary/ASCII detection, welding, degenerate triangles, errors that
// point at the file and line, and round trips through the writer.
#include <gtest/gtest.h>

#include <unistd.h>
#include "unit/temp_dir_test.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <tuple>

#include "bushel/core/input_error.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/io/stl.hpp"

namespace bushel::io {
namespace {

// Unit cube, vertex i at (i & 1, (i >> 1) & 1, (i >> 2) & 1); outward counter-clockwise faces.
constexpr std::array<std::array<int, 3>, 12> kCubeFaces{{{0, 2, 3},
                                                         {0, 3, 1},
                                                         {4, 5, 7},
                                                         {4, 7, 6},
                                                         {0, 1, 5},
                                                         {0, 5, 4},
                                                         {2, 6, 7},
                                                         {2, 7, 3},
                                                         {0, 4, 6},
                                                         {0, 6, 2},
                                                         {1, 3, 7},
                                                         {1, 7, 5}}};

Vec3 cube_vertex(int i) { return {double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)}; }

std::string ascii_facet(const Vec3& a, const Vec3& b, const Vec3& c) {
  std::string s = "  facet normal 0 0 0\n    outer loop\n";
  for (const Vec3& p : {a, b, c}) {
    s += "      vertex " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  }
  return s + "    endloop\n  endfacet\n";
}

std::string ascii_cube_facets() {
  std::string s;
  for (const auto& f : kCubeFaces) s += ascii_facet(cube_vertex(f[0]), cube_vertex(f[1]), cube_vertex(f[2]));
  return s;
}

std::string ascii_cube() { return "solid cube\n" + ascii_cube_facets() + "endsolid cube\n"; }

void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xffu);
}

// Written by hand, independent of the writer under test.
std::string binary_cube(const std::string& header_text) {
  std::string s = header_text;
  s.resize(80, '\0');
  put_u32(s, 12);
  for (const auto& f : kCubeFaces) {
    for (int k = 0; k < 3; ++k) put_u32(s, 0);  // normal left 0: the reader ignores it
    for (const int v : f) {
      const Vec3 p = cube_vertex(v);
      for (const double x : {p.x, p.y, p.z}) put_u32(s, std::bit_cast<std::uint32_t>(static_cast<float>(x)));
    }
    s += std::string(2, '\0');
  }
  return s;
}

void expect_cube(const TriangleMesh& m, double scale = 1.0) {
  ASSERT_EQ(m.size(), 12u);
  ASSERT_EQ(m.vertices.size(), 8u);
  // Vertices numbered in order of first appearance: 0, 2, 3, 1, 4, 5, 7, 6 of the cube.
  const std::array<int, 8> order{0, 2, 3, 1, 4, 5, 7, 6};
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(m.vertices[i], cube_vertex(order[i]) * scale) << i;
  for (std::size_t t = 0; t < 12; ++t) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.corner(t, k), cube_vertex(kCubeFaces[t][std::size_t(k)]) * scale);
  }
}

// x rounded to float32. Through a volatile: GCC 12.2 at -O2/-O3 (SLP vectorizer) drops the
// rounding when double(float(x)) is written for two neighbouring components of a struct.
double as_float32(double x) {
  const volatile float f = static_cast<float>(x);
  return static_cast<double>(f);
}

class StlFiles : public TempDirTest {};

TEST(Stl, AsciiCubeWeldsToEightVertices) {
  StlReport report;
  expect_cube(parse_stl(ascii_cube(), "cube.stl", 1.0, &report));
  EXPECT_EQ(report.triangles_read, 12u);
  EXPECT_EQ(report.degenerate_dropped, 0u);
  EXPECT_EQ(report.vertices, 8u);
}

TEST(Stl, BinaryCubeWeldsToEightVertices) {
  StlReport report;
  expect_cube(parse_stl(binary_cube("made by hand"), "cube.stl", 1.0, &report));
  EXPECT_EQ(report.triangles_read, 12u);
  EXPECT_EQ(report.vertices, 8u);
}

TEST(Stl, BinaryWhoseHeaderStartsWithSolidIsReadAsBinary) {
  expect_cube(parse_stl(binary_cube("solid cube exported by a CAD program"), "cube.stl"));
}

TEST(Stl, AsciiKeywordsInAnyCaseAnyWhitespaceSeveralSolids) {
  std::string text = "\xEF\xBB\xBF  SOLID first part\r\n";
  for (std::size_t t = 0; t < 6; ++t) {
    const auto& f = kCubeFaces[t];
    text += "Facet Normal +0 -0 1e0\n\tOuter\tLoop\n";
    for (const int v : f) {
      const Vec3 p = cube_vertex(v);
      text += "VERTEX\t" + std::to_string(p.x) + "  " + std::to_string(p.y) + " " + std::to_string(p.z) + "\r\n";
    }
    text += "EndLoop EndFacet\n";
  }
  text += "ENDSOLID first part\nsolid\n";
  for (std::size_t t = 6; t < 12; ++t) {
    const auto& f = kCubeFaces[t];
    text += ascii_facet(cube_vertex(f[0]), cube_vertex(f[1]), cube_vertex(f[2]));
  }
  text += "endsolid";  // no final newline
  expect_cube(parse_stl(text, "two.stl"));
}

TEST(Stl, ScaleMultipliesCoordinates) {
  expect_cube(parse_stl(ascii_cube(), "cube.stl", 0.001), 0.001);
  expect_cube(parse_stl(binary_cube(""), "cube.stl", 0.001), 0.001);
  for (const double bad : {0.0, -1.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
    try {
      parse_stl(ascii_cube(), "cube.stl", bad);
      FAIL() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), "scale");
      EXPECT_EQ(e.source(), "cube.stl");
    }
  }
}

TEST(Stl, NegativeZeroWeldsWithZero) {
  const std::string text = "solid s\n" + ascii_facet({0, 0, 0}, {1, 0, 0}, {0, 1, 0}) +
                           "facet normal 0 0 1\nouter loop\nvertex -0 -0.0 0\nvertex 0 1 0\nvertex -1 0 0\n"
                           "endloop\nendfacet\nendsolid s\n";
  const TriangleMesh m = parse_stl(text, "s.stl");
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.triangles[1][0], 0u);
  EXPECT_FALSE(std::signbit(m.vertices[0].x));
}

TEST(Stl, DegenerateTrianglesAreDroppedAndCounted) {
  const std::string text = "solid s\n" + ascii_cube_facets() +
                           ascii_facet({5, 5, 5}, {6, 6, 6}, {7, 7, 7}) +                    // collinear: zero area
                           ascii_facet({0, 0, 0}, {1, 0, 0}, {0, 0, 0}) +                    // two equal corners
                           ascii_facet({0.1, 0.2, 0.3}, {0.2, 0.4, 0.6}, {0.3, 0.6, 0.9}) +  // collinear up to rounding
                           "endsolid s\n";
  StlReport report;
  const TriangleMesh m = parse_stl(text, "s.stl", 1.0, &report);
  expect_cube(m);  // the dropped triangles add no vertices either
  EXPECT_EQ(report.triangles_read, 15u);
  EXPECT_EQ(report.degenerate_dropped, 3u);
  EXPECT_EQ(report.vertices, 8u);

  try {
    parse_stl("solid s\n" + ascii_facet({1, 2, 3}, {1, 2, 3}, {1, 2, 3}) + "endsolid s\n", "s.stl", 1.0, &report);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no triangles"), std::string::npos) << e.what();
    EXPECT_EQ(report.degenerate_dropped, 1u);
  }
}

// The line an ASCII error is reported on, and the message.
std::pair<int, std::string> ascii_error(const std::string& text) {
  try {
    parse_stl(text, "bad.stl");
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "bad.stl");
    return {e.line(), e.what()};
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return {0, ""};
}

TEST(Stl, AsciiErrorsPointAtTheLine) {
  const std::string head = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n";
  const std::string tail = "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
  const std::string good = head + "vertex 1 0 0\n" + tail;  // 9 lines
  int line = 0;
  std::string what;
  std::tie(line, what) = ascii_error(head + "vertex 1 zero 0\n" + tail);
  EXPECT_EQ(line, 5);
  EXPECT_EQ(what, "bad.stl:5: expected 'vertex x y z' with three numbers, got 'zero'");

  std::tie(line, what) = ascii_error(head + "vertex 1 0\n" + tail);  // two numbers, then 'vertex'
  EXPECT_EQ(line, 5);

  std::tie(line, what) = ascii_error(head + "vertex 1 nan 0\n" + tail);
  EXPECT_EQ(line, 5);
  EXPECT_NE(what.find("finite"), std::string::npos) << what;

  std::tie(line, what) = ascii_error(head + "endloop\nendfacet\nendsolid\n");
  EXPECT_EQ(line, 2);  // the facet's line
  EXPECT_NE(what.find("expected 3 vertices in a facet, got 1"), std::string::npos) << what;

  std::tie(line, what) = ascii_error(head + "vertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid\n");
  EXPECT_NE(what.find("got 4"), std::string::npos) << what;

  std::tie(line, what) = ascii_error("solid s\nfacet normal 0 0 1\nouter lop\n");
  EXPECT_EQ(line, 3);
  EXPECT_NE(what.find("expected 'outer loop', got 'lop'"), std::string::npos) << what;

  std::tie(line, what) = ascii_error(good.substr(0, good.find("endfacet")) + "\n\n");  // the file ends early
  EXPECT_NE(what.find("expected 'endfacet', got the end of the file"), std::string::npos) << what;
  EXPECT_EQ(line, 7);  // the last word, 'endloop'

  std::tie(line, what) = ascii_error(good + "garbage\n");
  EXPECT_EQ(line, 10);
  EXPECT_NE(what.find("expected 'solid' or the end of the file"), std::string::npos) << what;

  std::tie(line, what) = ascii_error("solid s\nendsolid s\n");
  EXPECT_NE(what.find("no triangles"), std::string::npos) << what;
  std::tie(line, what) = ascii_error("");
  EXPECT_NE(what.find("no triangles"), std::string::npos) << what;
  std::tie(line, what) = ascii_error("hello");
  EXPECT_NE(what.find("expected an STL file"), std::string::npos) << what;
}

TEST(Stl, TruncatedBinaryIsAnError) {
  for (const std::string header : {"binary", "solid looks like text"}) {
    const std::string full = binary_cube(header);
    try {
      parse_stl(full.substr(0, full.size() - 10), "cut.stl");
      FAIL();
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                "cut.stl: binary STL declares 12 triangles, which take 684 bytes, but holds 674 bytes (truncated, or "
                "not an STL file)");
    }
  }
  std::string nan_corner = binary_cube("");
  std::string nan_bits;
  put_u32(nan_bits, std::bit_cast<std::uint32_t>(std::numeric_limits<float>::quiet_NaN()));
  nan_corner.replace(84 + 50 + 12, 4, nan_bits);  // x of the first corner of triangle 2
  try {
    parse_stl(nan_corner, "nan.stl");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 2"), std::string::npos) << e.what();
  }
}

TEST(Stl, WriterProducesUnitNormalsAndANonSolidHeader) {
  const TriangleMesh cube = parse_stl(ascii_cube(), "cube.stl");
  const std::string bin = stl_bytes(cube, true, "cube");
  ASSERT_EQ(bin.size(), 84u + 50u * 12u);
  EXPECT_NE(bin.substr(0, 5), "solid");
  EXPECT_NE(bin.substr(0, 80).find("cube"), std::string::npos);
  for (std::size_t t = 0; t < 12; ++t) {
    float n[3];
    for (std::size_t d = 0; d < 3; ++d) {
      std::uint32_t u = 0;
      for (std::size_t i = 0; i < 4; ++i)
        u |= std::uint32_t(static_cast<unsigned char>(bin[84 + 50 * t + 4 * d + i])) << (8 * i);
      n[d] = std::bit_cast<float>(u);
    }
    const Vec3 e = cross(cube.corner(t, 1) - cube.corner(t, 0), cube.corner(t, 2) - cube.corner(t, 0));
    EXPECT_EQ((Vec3{static_cast<double>(n[0]), static_cast<double>(n[1]), static_cast<double>(n[2])}), e)
        << t;  // unit faces: the cross product is the unit normal
  }
  const std::string text = stl_bytes(cube, false, "cube");
  EXPECT_EQ(text.substr(0, 11), "solid cube\n");
  EXPECT_NE(text.find("facet normal 0.0000000000000000e+00 0.0000000000000000e+00 -1.0000000000000000e+00"),
            std::string::npos);

  TriangleMesh broken = cube;
  broken.triangles[3][1] = 99;
  EXPECT_THROW(stl_bytes(broken, true, "x"), std::invalid_argument);
}

TEST_F(StlFiles, RoundTripThroughFiles) {
  // Coordinates that are not short decimals: ASCII must still read back bit for bit.
  TriangleMesh mesh = parse_stl(ascii_cube(), "cube.stl");
  for (Vec3& v : mesh.vertices) v = v * (1.0 / 3.0) + Vec3{0.1, -0.2, 1e-7};
  for (const bool binary : {true, false}) {
    const std::string p = path(binary ? "cube_bin.stl" : "cube_ascii.stl");
    write_stl(p, mesh, binary, "cube");
    StlReport report;
    const TriangleMesh back = read_stl(p, 1.0, &report);
    EXPECT_EQ(back.triangles, mesh.triangles);
    ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
    EXPECT_EQ(report.vertices, 8u);
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      const Vec3& v = mesh.vertices[i];
      // Binary STL stores float32.
      const Vec3 expected = binary ? Vec3{as_float32(v.x), as_float32(v.y), as_float32(v.z)} : v;
      EXPECT_EQ(back.vertices[i], expected) << i << (binary ? " binary" : " ascii");
    }
  }
}

TEST_F(StlFiles, ErrorsNameThePath) {
  const std::string p = path("bad.stl");
  write_file_atomically(p, "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 x\n");
  try {
    read_stl(p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), p);
    EXPECT_EQ(e.line(), 5);
  }
  try {
    read_stl(path("missing.stl"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), path("missing.stl"));
  }
}

TEST_F(StlFiles, AtomicWriteReplacesAndLeavesNoTemporaryFile) {
  const std::string p = path("out.txt");
  write_file_atomically(p, "first version, longer than the second");
  write_file_atomically(p, std::string("second\0version", 14));
  EXPECT_EQ(read_text_file(p), std::string("second\0version", 14));
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir_)) ++files;
  EXPECT_EQ(files, 1);

  const std::string nowhere = path("no/such/dir/out.txt");
  try {
    write_file_atomically(nowhere, "x");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), nowhere);
  }
  EXPECT_THROW(write_file_atomically(dir_.string() + "/", "x"), InputError);
}

}  // namespace
}  // namespace bushel::io
