// VTK XML output: the numbers in the file are the numbers given (read back with plain string
// search, so the test needs no XML library), and pieces that do not fit together are refused.
#include <gtest/gtest.h>

#include <unistd.h>
#include "unit/temp_dir_test.hpp"

#include <charconv>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "bushel/io/csv.hpp"
#include "bushel/io/vtu.hpp"

namespace bushel::io {
namespace {

// The text between <DataArray ... Name="name" ...> and </DataArray> (the points array has no
// name: pass "" to get the first unnamed one).
std::string array_text(const std::string& xml, const std::string& name) {
  std::size_t pos = 0;
  while ((pos = xml.find("<DataArray", pos)) != std::string::npos) {
    const std::size_t close = xml.find('>', pos);
    const std::string tag = xml.substr(pos, close - pos);
    const bool match =
        name.empty() ? tag.find("Name=") == std::string::npos : tag.find("Name=\"" + name + "\"") != std::string::npos;
    if (match) {
      const std::size_t end = xml.find("</DataArray>", close);
      return xml.substr(close + 1, end - close - 1);
    }
    pos = close;
  }
  ADD_FAILURE() << "no DataArray named '" << name << "'";
  return {};
}

std::vector<double> numbers(const std::string& text) {
  std::vector<double> out;
  std::size_t pos = 0;
  while (true) {
    pos = text.find_first_not_of(" \n", pos);
    if (pos == std::string::npos) break;
    const std::size_t end = std::min(text.find_first_of(" \n", pos), text.size());
    double v = 0;
    const auto [ptr, ec] = std::from_chars(text.data() + pos, text.data() + end, v);
    EXPECT_TRUE(ec == std::errc() && ptr == text.data() + end) << text.substr(pos, end - pos);
    out.push_back(v);
    pos = end;
  }
  return out;
}

std::string attribute(const std::string& xml, const std::string& name) {
  const std::size_t pos = xml.find(name + "=\"");
  if (pos == std::string::npos) return "(missing)";
  const std::size_t start = pos + name.size() + 2;
  return xml.substr(start, xml.find('"', start) - start);
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t pos = s.find(what); pos != std::string::npos; pos = s.find(what, pos + 1)) ++n;
  return n;
}

// A unit square as two triangles, with awkward coordinates that must survive the text.
TriangleMesh square() {
  TriangleMesh m;
  m.vertices = {{0.1, 0.0, 1.0 / 3.0}, {1.0, 0.0, -2e-300}, {1.0, 1.0, 0.0}, {0.0, 1.0, 6.02214076e23}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

TEST(Vtu, SurfaceXmlHoldsTheCellsAndArrays) {
  VtuPiece p = surface_piece(square());
  p.cell_data.push_back({"area_m2", 1, {0.5, 0.25}});
  p.point_data.push_back({"velocity_m_s", 3, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}});
  const std::string xml = vtu_text(p);
  EXPECT_EQ(xml.rfind("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\"", 0), 0u);
  EXPECT_EQ(attribute(xml, "NumberOfPoints"), "4");
  EXPECT_EQ(attribute(xml, "NumberOfCells"), "2");
  EXPECT_EQ(numbers(array_text(xml, "connectivity")), (std::vector<double>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(numbers(array_text(xml, "offsets")), (std::vector<double>{3, 6}));
  EXPECT_EQ(numbers(array_text(xml, "types")), (std::vector<double>{5, 5}));
  EXPECT_EQ(numbers(array_text(xml, "area_m2")), (std::vector<double>{0.5, 0.25}));
  EXPECT_EQ(numbers(array_text(xml, "velocity_m_s")).size(), 12u);
  std::vector<double> xyz;
  for (const Vec3& v : square().vertices) xyz.insert(xyz.end(), {v.x, v.y, v.z});
  EXPECT_EQ(numbers(array_text(xml, "")), xyz);  // bit for bit
  // Arrays in the right sections, every element closed.
  EXPECT_LT(xml.find("<PointData>"), xml.find("velocity_m_s"));
  EXPECT_LT(xml.find("<CellData>"), xml.find("area_m2"));
  EXPECT_LT(xml.find("area_m2"), xml.find("</CellData>"));
  EXPECT_EQ(count(xml, "<DataArray"), 6u);
  EXPECT_EQ(count(xml, "</DataArray>"), 6u);
  EXPECT_NE(xml.find("Name=\"velocity_m_s\" NumberOfComponents=\"3\""), std::string::npos);
  EXPECT_EQ(xml.substr(xml.size() - 11), "</VTKFile>\n");
}

TEST(Vtu, PointCloudIsOneVertexCellPerPoint) {
  const std::vector<Vec3> pts{{0, 0, 0}, {1, 2, 3}, {-1, 0.5, 1e-3}};
  VtuPiece p = point_cloud_piece(pts);
  p.point_data.push_back({"radius_m", 1, {1e-3, 2e-3, 3e-3}});
  const std::string xml = vtu_text(p);
  EXPECT_EQ(attribute(xml, "NumberOfPoints"), "3");
  EXPECT_EQ(attribute(xml, "NumberOfCells"), "3");
  EXPECT_EQ(numbers(array_text(xml, "connectivity")), (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(numbers(array_text(xml, "offsets")), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(numbers(array_text(xml, "types")), (std::vector<double>{1, 1, 1}));
  EXPECT_EQ(numbers(array_text(xml, "radius_m")), (std::vector<double>{1e-3, 2e-3, 3e-3}));

  const std::string empty = vtu_text(point_cloud_piece({}));
  EXPECT_EQ(attribute(empty, "NumberOfPoints"), "0");
  EXPECT_TRUE(numbers(array_text(empty, "connectivity")).empty());
}

TEST(Vtu, MismatchedSizesThrow) {
  const VtuPiece good = surface_piece(square());
  EXPECT_NO_THROW(vtu_text(good));
  auto expect_invalid = [](const VtuPiece& p, const std::string& words) {
    try {
      vtu_text(p);
      ADD_FAILURE() << "no error, expected: " << words;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  VtuPiece p = good;
  p.cell_data.push_back({"area_m2", 1, {0.5}});
  expect_invalid(p, "array 'area_m2' has 1 values, expected 1 components x 2 cells = 2");
  p = good;
  p.point_data.push_back({"velocity_m_s", 3, std::vector<double>(4)});
  expect_invalid(p, "array 'velocity_m_s' has 4 values, expected 3 components x 4 points = 12");
  p = good;
  p.point_data.push_back({"", 1, std::vector<double>(4)});
  expect_invalid(p, "no name");
  p = good;
  p.point_data.push_back({"bad", 0, {}});
  expect_invalid(p, "0 components");
  p = good;
  p.point_data.push_back({"nan", 1, {0, 0, std::nan(""), 0}});
  expect_invalid(p, "array 'nan' value 2");
  p = good;
  p.types.pop_back();
  expect_invalid(p, "2 offsets but 1 cell types");
  p = good;
  p.offsets = {3, 3};
  expect_invalid(p, "offset of cell 1 is 3");
  p = good;
  p.connectivity.pop_back();
  expect_invalid(p, "the last offset is 6 but the connectivity has 5 indices");
  p = good;
  p.connectivity[4] = 4;
  expect_invalid(p, "connectivity[4] = 4 but there are 4 points");

  TriangleMesh broken = square();
  broken.triangles[1][2] = 7;
  EXPECT_THROW(surface_piece(broken), std::invalid_argument);
}

class VtuFiles : public TempDirTest {};

TEST_F(VtuFiles, WrittenFileReadsBack) {
  VtuPiece p = surface_piece(square());
  p.cell_data.push_back({"pressure_Pa", 1, {101325.0, 0.1}});
  write_vtu(path("square.vtu"), p);
  const std::string xml = read_text_file(path("square.vtu"));
  EXPECT_EQ(xml, vtu_text(p));
  EXPECT_EQ(attribute(xml, "NumberOfCells"), "2");
  EXPECT_EQ(numbers(array_text(xml, "pressure_Pa")), (std::vector<double>{101325.0, 0.1}));
  EXPECT_EQ(numbers(array_text(xml, "connectivity")), (std::vector<double>{0, 1, 2, 0, 2, 3}));
}

TEST_F(VtuFiles, CollectionListsTimesAndFiles) {
  write_pvd(path("run.pvd"), {{0.0, "frame_0.vtu"}, {0.0125, "frame_1.vtu"}, {1.5, "a&b.vtu"}});
  const std::string xml = read_text_file(path("run.pvd"));
  EXPECT_NE(xml.find("<VTKFile type=\"Collection\" version=\"0.1\""), std::string::npos);
  EXPECT_EQ(count(xml, "<DataSet "), 3u);
  EXPECT_NE(xml.find("timestep=\"0.0125\" group=\"\" part=\"0\" file=\"frame_1.vtu\"/>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("file=\"a&amp;b.vtu\""), std::string::npos) << xml;
  EXPECT_THROW(write_pvd(path("bad.pvd"), {{std::nan(""), "x.vtu"}}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path("bad.pvd")));
}

}  // namespace
}  // namespace bushel::io
