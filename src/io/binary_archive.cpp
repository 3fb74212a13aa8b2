#include "bushel/io/binary_archive.hpp"

#include <xxhash.h>

#include <fmt/format.h>

namespace bushel::io {

std::uint64_t checksum(std::string_view bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

void BinaryWriter::put_section(std::string_view name, const BinaryWriter& body) {
  put(std::string(name));
  put(static_cast<std::uint64_t>(body.bytes_.size()));
  put(static_cast<std::uint64_t>(checksum(body.bytes_)));
  bytes_.append(body.bytes_);
}

BinaryReader BinaryReader::section(std::string_view name) {
  std::uint64_t length = 0;
  std::string found;
  get(found);  // (its length is checked against what is left, like every string's)
  if (found != name) damaged(fmt::format("section '{}' expected where the data holds another", name));
  get(length);
  const auto sum = get<std::uint64_t>();
  if (length > bytes_.size() - at_) damaged(fmt::format("section '{}' ends early (cut off?)", name));
  const std::string_view body = bytes_.substr(at_, length);
  if (checksum(body) != sum) {
    damaged(fmt::format("section '{}' does not match its checksum", name));
  }
  at_ += length;
  return {body, source_ + " (section " + std::string(name) + ")"};
}

void BinaryReader::damaged(const std::string& what) const {
  throw InputError("a damaged checkpoint (" + what + "): it cannot be continued; start the run again").at(source_);
}

}  // namespace bushel::io
