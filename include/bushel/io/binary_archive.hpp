#pragma once
// A plain binary archive for checkpoints: values and vectors of trivially copyable types and
// strings, written in the machine's byte order, read back with every length checked against
// what is left (a truncated or foreign file is an InputError, never a crash). A checkpoint is
// only read back on the machine kind that wrote it.

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "bushel/core/input_error.hpp"

namespace bushel::io {

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

 private:
  void need(std::size_t n) const {
    if (bytes_.size() - at_ < n) throw InputError("truncated or not a bushel checkpoint").at(source_);
  }
  std::uint64_t count(std::size_t element) {
    std::uint64_t n = 0;
    get(n);
    if (element > 0 && n > (bytes_.size() - at_) / element) {
      throw InputError("truncated or not a bushel checkpoint").at(source_);
    }
    return n;
  }
  std::string_view bytes_;
  std::string source_;
  std::size_t at_ = 0;
};

}  // namespace bushel::io
