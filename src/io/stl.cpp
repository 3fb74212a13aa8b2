#include "bushel/io/stl.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "bushel/core/input_error.hpp"
#include "bushel/core/require.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/csv.hpp"

namespace bushel::io {
namespace {

constexpr std::size_t kHeaderBytes = 80;
constexpr std::size_t kBinaryPrefix = 84;  // header + uint32 triangle count
constexpr std::size_t kFacetBytes = 50;    // normal, 3 corners (12 float32), uint16 attribute

// A triangle whose two edges from one corner are parallel to within rounding of the cross
// product (sine of the corner angle below this) has no usable normal: dropped as degenerate.
constexpr double kDegenerateSine = 1e-14;

// ---- welding -------------------------------------------------------------------------------

// The bit patterns of a corner: welding is by identity, so that it never merges two corners a
// CAD program meant to be distinct, however close.
struct CornerKey {
  std::uint64_t x, y, z;
  friend bool operator==(const CornerKey&, const CornerKey&) = default;
};

struct CornerKeyHash {
  static std::uint64_t mix(std::uint64_t h) {  // splitmix64 finaliser
    h ^= h >> 30;
    h *= 0xbf58476d1ce4e5b9ULL;
    h ^= h >> 27;
    h *= 0x94d049bb133111ebULL;
    return h ^ (h >> 31);
  }
  std::size_t operator()(const CornerKey& k) const { return static_cast<std::size_t>(mix(mix(mix(k.x) ^ k.y) ^ k.z)); }
};

// Adding +0.0 turns -0.0 into +0.0 (exporters write both for the same plane) and leaves every
// other value unchanged.
CornerKey key_of(const Vec3& p) {
  return {std::bit_cast<std::uint64_t>(p.x + 0.0), std::bit_cast<std::uint64_t>(p.y + 0.0),
          std::bit_cast<std::uint64_t>(p.z + 0.0)};
}

class MeshBuilder {
 public:
  /// Adds a triangle of scaled, finite corners unless it is degenerate.
  void add(const std::array<Vec3, 3>& c, const std::string& source) {
    ++read_;
    const std::array<CornerKey, 3> keys{key_of(c[0]), key_of(c[1]), key_of(c[2])};
    const Vec3 e1 = c[1] - c[0];
    const Vec3 e2 = c[2] - c[0];
    const double limit = kDegenerateSine * kDegenerateSine * norm2(e1) * norm2(e2);
    if (keys[0] == keys[1] || keys[1] == keys[2] || keys[0] == keys[2] || !(norm2(cross(e1, e2)) > limit)) {
      ++dropped_;
      return;
    }
    std::array<std::uint32_t, 3> tri{};
    for (std::size_t k = 0; k < 3; ++k) {
      const auto [it, inserted] = index_.try_emplace(keys[k], static_cast<std::uint32_t>(mesh_.vertices.size()));
      if (inserted) {
        if (mesh_.vertices.size() >= std::numeric_limits<std::uint32_t>::max()) {
          throw InputError("the mesh has more distinct vertices than 32-bit indices can hold").at(source);
        }
        mesh_.vertices.push_back({c[k].x + 0.0, c[k].y + 0.0, c[k].z + 0.0});
      }
      tri[k] = it->second;
    }
    mesh_.triangles.push_back(tri);
  }

  TriangleMesh finish(const std::string& source, StlReport* report) {
    if (report != nullptr) *report = {read_, dropped_, mesh_.vertices.size()};
    if (mesh_.triangles.empty()) {
      throw InputError(read_ == 0 ? std::string("no triangles: the file holds no facets")
                                  : fmt::format("no triangles: all {} facets are degenerate (zero area)", read_))
          .at(source);
    }
    return std::move(mesh_);
  }

  void reserve(std::size_t triangles) {
    mesh_.triangles.reserve(triangles);
    mesh_.vertices.reserve(triangles / 2 + 3);  // a closed surface has about half as many vertices
    index_.reserve(triangles / 2 + 3);
  }

 private:
  TriangleMesh mesh_;
  std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> index_;
  std::size_t read_ = 0;
  std::size_t dropped_ = 0;
};

// ---- binary --------------------------------------------------------------------------------

std::uint32_t load_u32(std::string_view bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v |= std::uint32_t{static_cast<unsigned char>(bytes[at + i])} << (8 * i);
  return v;
}

void store_u32(std::string& out, std::size_t at, std::uint32_t v) {
  for (std::size_t i = 0; i < 4; ++i) out[at + i] = static_cast<char>((v >> (8 * i)) & 0xffu);
}

void store_f32(std::string& out, std::size_t at, double v) {
  store_u32(out, at, std::bit_cast<std::uint32_t>(static_cast<float>(v)));
}

bool is_binary(std::string_view bytes) {
  if (bytes.size() < kBinaryPrefix) return false;
  const std::uint64_t n = load_u32(bytes, kHeaderBytes);
  return bytes.size() == kBinaryPrefix + kFacetBytes * n;
}

TriangleMesh parse_binary(std::string_view bytes, const std::string& source, double scale, StlReport* report) {
  const std::size_t n = load_u32(bytes, kHeaderBytes);
  MeshBuilder builder;
  builder.reserve(n);
  for (std::size_t t = 0; t < n; ++t) {
    const std::size_t base = kBinaryPrefix + kFacetBytes * t + 12;  // skip the stored normal
    std::array<Vec3, 3> c;
    for (std::size_t k = 0; k < 3; ++k) {
      double xyz[3];
      for (std::size_t d = 0; d < 3; ++d) {
        const float f = std::bit_cast<float>(load_u32(bytes, base + 12 * k + 4 * d));
        xyz[d] = static_cast<double>(f) * scale;
        if (!std::isfinite(xyz[d])) {
          throw InputError(
              fmt::format("triangle {} (byte {}): expected finite vertex coordinates, got {}{}", t + 1,
                          base + 12 * k + 4 * d, static_cast<double>(f),
                          std::isfinite(f) ? fmt::format(" (not finite after scaling by {})", scale) : std::string()))
              .at(source);
        }
      }
      c[k] = {xyz[0], xyz[1], xyz[2]};
    }
    builder.add(c, source);
  }
  return builder.finish(source, report);
}

// ---- ASCII ---------------------------------------------------------------------------------

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return lower(x) == y; });
}

struct Token {
  std::string_view text;  // empty at the end of the input
  int line = 0;           // 1-based; at the end, the line of the last word
};

// Whitespace-separated words with the line each starts on.
class Tokenizer {
 public:
  explicit Tokenizer(std::string_view text) : text_(text) {}

  Token next() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    if (pos_ == start) return {{}, last_line_};  // the end: errors point at the last word
    last_line_ = line_;
    return {text_.substr(start, pos_ - start), line_};
  }
  /// Skips the rest of the current line (the free-form name after 'solid' and 'endsolid').
  void skip_line() {
    const auto nl = text_.find('\n', pos_);
    pos_ = nl == std::string_view::npos ? text_.size() : nl;
  }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int last_line_ = 1;
};

bool parse_double(std::string_view s, double& out) {
  if (s.size() > 1 && s.front() == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

std::string shown(const Token& t) {
  return t.text.empty() ? std::string("the end of the file") : fmt::format("'{}'", t.text);
}

class AsciiParser {
 public:
  AsciiParser(std::string_view text, const std::string& source, double scale)
      : tok_(text), source_(source), scale_(scale) {}

  TriangleMesh parse(StlReport* report) {
    for (Token t = tok_.next(); !t.text.empty(); t = tok_.next()) {
      if (!iequals(t.text, "solid"))
        fail(t.line, fmt::format("expected 'solid' or the end of the file, got {}", shown(t)));
      tok_.skip_line();
      parse_solid();
    }
    return builder_.finish(source_, report);
  }

 private:
  [[noreturn]] void fail(int line, const std::string& problem) const { throw InputError(problem).at(source_, line); }

  void expect(std::string_view keyword, std::string_view what) {
    const Token t = tok_.next();
    if (!iequals(t.text, keyword)) fail(t.line, fmt::format("expected {}, got {}", what, shown(t)));
  }

  // Three numbers after a keyword; errors point at the keyword's line.
  std::array<double, 3> numbers(int line, std::string_view what) {
    std::array<double, 3> v{};
    for (double& x : v) {
      const Token t = tok_.next();
      if (!parse_double(t.text, x)) fail(line, fmt::format("expected {} with three numbers, got {}", what, shown(t)));
    }
    return v;
  }

  void parse_solid() {
    while (true) {
      const Token t = tok_.next();
      if (iequals(t.text, "endsolid")) {
        tok_.skip_line();
        return;
      }
      if (!iequals(t.text, "facet")) {
        fail(t.line, fmt::format("expected 'facet' or 'endsolid', got {}", shown(t)));
      }
      parse_facet(t.line);
    }
  }

  void parse_facet(int facet_line) {
    expect("normal", "'facet normal nx ny nz'");
    numbers(facet_line, "'facet normal nx ny nz'");  // recomputed from the corners where needed
    expect("outer", "'outer loop'");
    expect("loop", "'outer loop'");
    std::array<Vec3, 3> c;
    int count = 0;
    while (true) {
      const Token t = tok_.next();
      if (iequals(t.text, "endloop")) break;
      if (!iequals(t.text, "vertex")) {
        fail(t.line, fmt::format("expected 'vertex x y z' or 'endloop', got {}", shown(t)));
      }
      const auto v = numbers(t.line, "'vertex x y z'");
      for (const double x : v) {
        if (!std::isfinite(x)) fail(t.line, fmt::format("expected finite vertex coordinates, got {}", x));
        if (!std::isfinite(x * scale_)) {
          fail(t.line, fmt::format("vertex coordinate {} is not finite after scaling by {}", x, scale_));
        }
      }
      if (count < 3) c[static_cast<std::size_t>(count)] = Vec3{v[0] * scale_, v[1] * scale_, v[2] * scale_};
      ++count;
    }
    if (count != 3) fail(facet_line, fmt::format("expected 3 vertices in a facet, got {}", count));
    expect("endfacet", "'endfacet'");
    builder_.add(c, source_);
  }

  Tokenizer tok_;
  const std::string& source_;
  double scale_;
  MeshBuilder builder_;
};

// ---- format detection ----------------------------------------------------------------------

constexpr std::string_view kBom = "\xEF\xBB\xBF";  // UTF-8 byte order mark, written by some editors

std::string_view skip_bom_and_space(std::string_view s) {
  if (s.starts_with(kBom)) s.remove_prefix(kBom.size());
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  return s;
}

// Text that begins with 'solid' and holds no NUL byte (binary facets end in two NUL attribute
// bytes, headers are NUL-padded) is ASCII.
bool looks_ascii(std::string_view bytes) {
  const std::string_view s = skip_bom_and_space(bytes);
  return s.size() >= 5 && iequals(s.substr(0, 5), "solid") && (s.size() == 5 || is_space(s[5])) &&
         bytes.find('\0') == std::string_view::npos;
}

}  // namespace

TriangleMesh parse_stl(std::string_view bytes, const std::string& source, double scale, StlReport* report) {
  try {
    require_positive(scale, "scale", "0.001 for a file in millimetres");
  } catch (const InputError& e) {
    throw e.at(source);
  }
  if (is_binary(bytes)) return parse_binary(bytes, source, scale, report);
  if (looks_ascii(bytes)) {
    std::string_view text = bytes;
    if (text.starts_with(kBom)) text.remove_prefix(kBom.size());
    return AsciiParser(text, source, scale).parse(report);
  }
  if (skip_bom_and_space(bytes).empty()) throw InputError("no triangles: the file is empty").at(source);
  if (bytes.size() >= kBinaryPrefix) {
    const std::uint64_t n = load_u32(bytes, kHeaderBytes);
    throw InputError(fmt::format("binary STL declares {} triangles, which take {} bytes, but holds {} bytes "
                                 "(truncated, or not an STL file)",
                                 n, kBinaryPrefix + kFacetBytes * n, bytes.size()))
        .at(source);
  }
  throw InputError(fmt::format("expected an STL file (ASCII starting with 'solid', or binary with an 84-byte "
                               "header), got {} bytes of something else",
                               bytes.size()))
      .at(source);
}

TriangleMesh read_stl(const std::string& path, double scale, StlReport* report) {
  return parse_stl(read_text_file(path), path, scale, report);
}

std::string stl_bytes(const TriangleMesh& mesh, bool binary, const std::string& name) {
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    for (const auto i : mesh.triangles[t]) {
      if (i >= mesh.vertices.size()) {
        throw std::invalid_argument(
            fmt::format("stl_bytes: triangle {} references vertex {} but the mesh has {}", t, i, mesh.vertices.size()));
      }
    }
  }
  const auto unit_normal = [&](std::size_t t) {
    const Vec3 n = cross(mesh.corner(t, 1) - mesh.corner(t, 0), mesh.corner(t, 2) - mesh.corner(t, 0));
    const double len = norm(n);
    return len > 0.0 ? n / len : Vec3{};
  };
  if (binary) {
    if (mesh.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw std::invalid_argument(fmt::format("stl_bytes: {} triangles do not fit a binary STL", mesh.size()));
    }
    std::string out(kBinaryPrefix + kFacetBytes * mesh.size(), '\0');
    // Not starting with "solid", so that readers that only look at the first bytes see binary.
    const std::string header = fmt::format("binary STL from bushel: {}", name);
    std::copy_n(header.begin(), std::min(header.size(), kHeaderBytes), out.begin());
    store_u32(out, kHeaderBytes, static_cast<std::uint32_t>(mesh.size()));
    for (std::size_t t = 0; t < mesh.size(); ++t) {
      const std::size_t base = kBinaryPrefix + kFacetBytes * t;
      const Vec3 n = unit_normal(t);
      for (int d = 0; d < 3; ++d) store_f32(out, base + 4 * static_cast<std::size_t>(d), n[d]);
      for (int k = 0; k < 3; ++k) {
        for (int d = 0; d < 3; ++d) {
          store_f32(out, base + 12 + 12 * static_cast<std::size_t>(k) + 4 * static_cast<std::size_t>(d),
                    mesh.corner(t, k)[d]);
        }
      }  // the attribute bytes stay 0
    }
    return out;
  }
  std::string solid = name;  // the name runs to the end of the line
  std::replace_if(
      solid.begin(), solid.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  std::string out = fmt::format("solid {}\n", solid);
  auto it = std::back_inserter(out);
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const Vec3 n = unit_normal(t);
    // 17 significant digits: every double reads back exactly.
    fmt::format_to(it, "  facet normal {:.16e} {:.16e} {:.16e}\n    outer loop\n", n.x, n.y, n.z);
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.corner(t, k);
      fmt::format_to(it, "      vertex {:.16e} {:.16e} {:.16e}\n", p.x, p.y, p.z);
    }
    out += "    endloop\n  endfacet\n";
  }
  fmt::format_to(it, "endsolid {}\n", solid);
  return out;
}

void write_stl(const std::string& path, const TriangleMesh& mesh, bool binary, const std::string& name) {
  write_file_atomically(path, stl_bytes(mesh, binary, name));
}

}  // namespace bushel::io
