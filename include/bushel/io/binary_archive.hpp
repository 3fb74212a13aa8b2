#pragma once
// A plain binary archive for checkpoints: values and vectors of trivially copyable types and
// strings, written in the machine's byte order, read back with every length checked against
// what is left (a truncated or foreign file is an InputError, never a crash). A checkpoint is
// only read back on the machine kind that wrote it. Its parts are named, versioned sections,
// each written and read by the component it belongs to: a name, a version, a length and an
// XXH3-64 checksum of the bytes, so that a flipped bit or a cut file is found before any of it
// is read, not restarted into a different run. SectionTable finds them by name, in any order.

#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "bushel/core/input_error.hpp"

namespace bushel::io {

/// The checksum of a section's bytes (XXH3, 64 bits).
std::uint64_t checksum(std::string_view bytes);

class BinaryWriter {
 public:
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void put(const T& v) { bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T)); }
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void put(const std::vector<T>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void put(const std::vector<bool>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    for (const bool b : v) put(static_cast<std::uint8_t>(b));
  }
  void put(const std::string& s) {
    put(static_cast<std::uint64_t>(s.size()));
    bytes_.append(s);
  }
  /// Appends `body` as the section `name` in its `version`, with its length and checksum.
  void put_section(std::string_view name, std::uint32_t version, const BinaryWriter& body);
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class BinaryReader {
 public:
  /// `source` names the data in errors.
  BinaryReader(std::string_view bytes, std::string source) : bytes_(bytes), source_(std::move(source)) {}

  template <class T>
  requires std::is_trivially_copyable_v<T>
  void get(T& v) {
    need(sizeof(T));
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
  }
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void get(std::vector<T>& v) {
    const std::uint64_t n = count(sizeof(T));
    v.resize(n);
    if (n > 0) std::memcpy(v.data(), bytes_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
  }
  /// A flag: a byte that must be 0 or 1 (any other value would be undefined as a bool).
  void get(bool& v) {
    std::uint8_t b = 0;
    get(b);
    if (b > 1) damaged("a flag that is neither 0 nor 1");
    v = b != 0;
  }
  void get(std::vector<bool>& v) {
    const std::uint64_t n = count(1);
    v.resize(n);
    for (std::uint64_t i = 0; i < n; ++i) {
      std::uint8_t b = 0;
      get(b);
      v[i] = b != 0;
    }
  }
  void get(std::string& s) {
    const std::uint64_t n = count(1);
    s.assign(bytes_.data() + at_, n);
    at_ += n;
  }
  template <class T>
  T get() {
    T v{};
    get(v);
    return v;
  }
  bool done() const { return at_ == bytes_.size(); }
  /// The next n bytes, unread (checked against what is left), then skipped.
  std::string_view take(std::uint64_t n) {
    if (n > bytes_.size() - at_) damaged("it ends early (cut off?)");
    const std::string_view b = bytes_.substr(at_, n);
    at_ += n;
    return b;
  }
  const std::string& source() const { return source_; }
  /// A count of items that take at least `bytes_each` bytes each, checked against what is
  /// left before anything is sized by it.
  std::uint64_t get_count(std::size_t bytes_each) { return count(bytes_each); }
  /// Throws the InputError of damaged data, naming the source and `what`.
  [[noreturn]] void damaged(const std::string& what) const;

 private:
  void need(std::size_t n) const {
    if (bytes_.size() - at_ < n) damaged("it ends early");
  }
  std::uint64_t count(std::size_t element) {
    std::uint64_t n = 0;
    get(n);
    if (element > 0 && n > (bytes_.size() - at_) / element) damaged("a count larger than the data that follows");
    return n;
  }
  std::string_view bytes_;
  std::string source_;
  std::size_t at_ = 0;
};

/// The sections that follow in a reader, by name (BinaryWriter::put_section), every checksum
/// verified when the table is made. A component asks for its section and reads it with the
/// version it finds; a section that is absent takes the component's defaults where it may
/// (find), and is damage where it must be there (get).
class SectionTable {
 public:
  struct Section {
    std::uint32_t version = 0;
    BinaryReader body;  ///< over the section's bytes (borrowed from the table's reader)
  };
  /// Reads every section to the end of `in`; a section twice, a cut one or a checksum that
  /// does not match is damage.
  explicit SectionTable(BinaryReader& in);
  /// Section `name`, if present; damage if its version is newer than `newest` (a later build's).
  std::optional<Section> find(std::string_view name, std::uint32_t newest) const;
  /// Section `name`; damage if it is absent.
  Section get(std::string_view name, std::uint32_t newest) const;
  /// Damage if a section's name is none of `known`: the checksums cover the bodies, not the
  /// names, so a flipped bit in an optional section's name would otherwise pass as its absence.
  void expect_known(std::span<const std::string_view> known) const;
  /// Reads section `name` with `read(BinaryReader&)`, which must read every byte of it; an
  /// absent section is damage if `required`, else skipped. Returns whether it was there.
  template <class F>
  bool read(std::string_view name, std::uint32_t newest, bool required, F&& read) const {
    std::optional<Section> s = required ? std::optional(get(name, newest)) : find(name, newest);
    if (!s) return false;
    read(s->body);
    expect_end(s->body, name);
    return true;
  }
  /// Damage unless every byte of the section was read.
  static void expect_end(const BinaryReader& body, std::string_view name);

 private:
  struct Entry {
    std::string name;
    std::uint32_t version;
    std::string_view bytes;
  };
  const BinaryReader* in_;
  std::vector<Entry> entries_;
};

}  // namespace bushel::io
