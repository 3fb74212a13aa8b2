#include "bushel/io/binary_archive.hpp"

#include <algorithm>

#include <xxhash.h>

#include <fmt/format.h>

namespace bushel::io {

std::uint64_t checksum(std::string_view bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

void BinaryWriter::put_section(std::string_view name, std::uint32_t version, const BinaryWriter& body) {
  put(std::string(name));
  put(version);
  put(static_cast<std::uint64_t>(body.bytes_.size()));
  put(static_cast<std::uint64_t>(checksum(body.bytes_)));
  bytes_.append(body.bytes_);
}

SectionTable::SectionTable(BinaryReader& in) : in_(&in) {
  while (!in.done()) {
    Entry e;
    in.get(e.name);  // (its length is checked against what is left, like every string's)
    in.get(e.version);
    const auto length = in.get<std::uint64_t>();
    const auto sum = in.get<std::uint64_t>();
    e.bytes = in.take(length);  // (damage if the file ends first)
    if (checksum(e.bytes) != sum) in.damaged(fmt::format("section '{}' does not match its checksum", e.name));
    // (the checksum covers the body only; versions count from 1, so a 0 is a flipped bit)
    if (e.version == 0) in.damaged(fmt::format("section '{}' of version 0", e.name));
    for (const Entry& other : entries_) {
      if (other.name == e.name) in.damaged(fmt::format("section '{}' twice", e.name));
    }
    entries_.push_back(std::move(e));
  }
}

std::optional<SectionTable::Section> SectionTable::find(std::string_view name, std::uint32_t newest) const {
  for (const Entry& e : entries_) {
    if (e.name != name) continue;
    if (e.version > newest) {
      in_->damaged(fmt::format("section '{}' of version {}, newer than this build's {}", name, e.version, newest));
    }
    return Section{e.version, BinaryReader(e.bytes, in_->source() + " (section " + std::string(name) + ")")};
  }
  return std::nullopt;
}

SectionTable::Section SectionTable::get(std::string_view name, std::uint32_t newest) const {
  auto s = find(name, newest);
  if (!s) in_->damaged(fmt::format("it has no section '{}'", name));
  return std::move(*s);
}

void SectionTable::expect_known(std::span<const std::string_view> known) const {
  for (const Entry& e : entries_) {
    if (std::find(known.begin(), known.end(), e.name) == known.end()) {
      in_->damaged(fmt::format("a section of unknown name '{}'", e.name));
    }
  }
}

void SectionTable::expect_end(const BinaryReader& body, std::string_view name) {
  if (!body.done()) body.damaged(fmt::format("unexpected data at the end of section '{}'", name));
}

void BinaryReader::damaged(const std::string& what) const {
  throw InputError("a damaged checkpoint (" + what + "): it cannot be continued; start the run again").at(source_);
}

}  // namespace bushel::io
