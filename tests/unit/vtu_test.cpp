// VTK XML output: the numbers in the file are the numbers given (read back with plain string
// search, so the test needs no XML library; binary arrays decoded here with zlib as VTK's
// reader does), and pieces that do not fit together are refused.
#include <gtest/gtest.h>
#include <zlib.h>

#include <unistd.h>
#include "unit/temp_dir_test.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>
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

// The values of the appended array `name` of a binary file, as T: its offset from the
// DataArray tag; then VTK's block header (UInt64: blocks, block size, last partial size,
// compressed sizes) and the zlib blocks, each inflated.
template <class T>
std::vector<T> appended(const std::string& file, const std::string& name) {
  const std::size_t tag = name.empty() ? file.find("<DataArray type=\"Float64\" NumberOfComponents=\"3\" format")
                                       : file.find("Name=\"" + name + "\"");
  EXPECT_NE(tag, std::string::npos) << name;
  const std::size_t offset = std::stoul(attribute(file.substr(tag), "offset"));
  const char* data = file.data() + file.find("<AppendedData encoding=\"raw\">") + 1;
  data = std::strchr(data, '_') + 1 + offset;
  std::uint64_t head[3];
  std::memcpy(head, data, sizeof head);
  const std::uint64_t blocks = head[0], block = head[1], last = head[2];
  std::string bytes;
  const char* z = data + (3 + blocks) * 8;
  for (std::uint64_t k = 0; k < blocks; ++k) {
    std::uint64_t zsize = 0;
    std::memcpy(&zsize, data + (3 + k) * 8, 8);
    uLongf size = (k + 1 == blocks && last != 0) ? last : block;
    std::string out(size, '\0');
    EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(z), zsize), Z_OK);
    EXPECT_EQ(size, out.size());
    bytes += out;
    z += zsize;
  }
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), bytes.size());
  return values;
}

TEST(Vtu, BinaryFileHoldsTheSameValuesCompressed) {
  // 5,000 points: several 32 KiB blocks per array, the last one partial.
  std::vector<Vec3> pts;
  for (int i = 0; i < 5000; ++i) pts.push_back({1e-3 * i, -1.0 / (i + 1), 6.02214076e23});
  VtuPiece p = point_cloud_piece(pts);
  VtuArray id{"body_id", 1, {}, VtuType::uint32}, type{"type", 1, {}, VtuType::int32};
  for (int i = 0; i < 5000; ++i) id.values.push_back(4000000000.0 - i), type.values.push_back(i % 3 - 1);
  p.point_data = {id, type};
  p.field_strings = {{"type_names", {"large", "", "a&b"}}};
  const std::string file = vtu_file(p, VtuEncoding::zlib);
  EXPECT_NE(file.find("version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" "
                      "compressor=\"vtkZLibDataCompressor\""),
            std::string::npos);
  std::vector<double> xyz;
  for (const Vec3& q : pts) xyz.insert(xyz.end(), {q.x, q.y, q.z});
  EXPECT_EQ(appended<double>(file, ""), xyz);
  const std::vector<std::uint32_t> ids = appended<std::uint32_t>(file, "body_id");
  ASSERT_EQ(ids.size(), 5000u);
  EXPECT_EQ(ids[0], 4000000000u);
  EXPECT_EQ(ids[4999], 3999995001u);
  const std::vector<std::int32_t> types = appended<std::int32_t>(file, "type");
  EXPECT_EQ(types[0], -1);
  EXPECT_EQ(types[4], 0);
  const std::vector<std::int64_t> offsets = appended<std::int64_t>(file, "offsets");
  EXPECT_EQ(offsets.back(), 5000);
  EXPECT_EQ(appended<std::uint8_t>(file, "types"), std::vector<std::uint8_t>(5000, kVtkVertex));
  // the strings as VTK writes them in ASCII: character codes, each string ended by a 0
  EXPECT_EQ(numbers(array_text(file, "type_names")),
            (std::vector<double>{108, 97, 114, 103, 101, 0, 0, 97, 38, 98, 0}));
  EXPECT_LT(file.size(), vtu_text(p).size() / 2);
}

TEST(Vtu, IntegerArraysTakeOnlyWholeNumbersInRange) {
  auto piece = [](double v, VtuType t) {
    VtuPiece p = point_cloud_piece(std::vector<Vec3>{{0, 0, 0}});
    p.point_data = {{"id", 1, {v}, t}};
    return p;
  };
  EXPECT_NO_THROW(vtu_text(piece(-2147483648.0, VtuType::int32)));
  EXPECT_NO_THROW(vtu_text(piece(4294967295.0, VtuType::uint32)));
  for (const auto& [v, t] : std::vector<std::pair<double, VtuType>>{{0.5, VtuType::int32},
                                                                    {2147483648.0, VtuType::int32},
                                                                    {-1.0, VtuType::uint32},
                                                                    {4294967296.0, VtuType::uint32}}) {
    try {
      vtu_file(piece(v, t), VtuEncoding::zlib);
      ADD_FAILURE() << v;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("expected a whole number from"), std::string::npos) << e.what();
    }
  }
  VtuPiece p = piece(1.0, VtuType::int32);
  p.field_strings = {{"names", {std::string("a\0b", 3)}}};
  EXPECT_THROW(vtu_text(p), std::invalid_argument);
  EXPECT_EQ(numbers(array_text(vtu_text(piece(7.0, VtuType::int32)), "id")), std::vector<double>{7.0});
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
