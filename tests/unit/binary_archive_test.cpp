// Checkpoint sections (binary_archive.hpp): found by name in any order, with their versions;
// absent, newer, repeated or damaged ones are told apart.

#include <gtest/gtest.h>

#include <array>
#include <string>

#include "bushel/core/input_error.hpp"
#include "bushel/io/binary_archive.hpp"

namespace bushel::io {
namespace {

std::string two_sections() {
  BinaryWriter out, a, b;
  a.put(std::uint64_t{42});
  b.put(std::string("bee"));
  out.put_section("a", 1, a);
  out.put_section("b", 2, b);
  return out.bytes();
}

std::string damage_of(const std::string& bytes, std::string_view name, std::uint32_t newest) {
  try {
    BinaryReader in(bytes, "f");
    (void)SectionTable(in).get(name, newest);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(read)";
}

TEST(SectionTable, FindsSectionsByNameWithTheirVersions) {
  const std::string bytes = two_sections();
  BinaryReader in(bytes, "f");
  const SectionTable t(in);
  auto b = t.get("b", 2);  // (in any order)
  EXPECT_EQ(b.version, 2u);
  EXPECT_EQ(b.body.get<std::string>(), "bee");
  auto a = t.get("a", 1);
  EXPECT_EQ(a.body.get<std::uint64_t>(), 42u);
  EXPECT_TRUE(a.body.done());
  EXPECT_FALSE(t.find("c", 1).has_value());
}

TEST(SectionTable, RefusesAbsentNewerRepeatedAndDamagedSections) {
  const std::string bytes = two_sections();
  EXPECT_NE(damage_of(bytes, "c", 1).find("it has no section 'c'"), std::string::npos);
  EXPECT_NE(damage_of(bytes, "b", 1).find("section 'b' of version 2, newer than this build's 1"), std::string::npos);
  EXPECT_NE(damage_of(bytes + bytes, "a", 1).find("section 'a' twice"), std::string::npos);
  std::string flipped = bytes;
  flipped.back() = static_cast<char>(flipped.back() ^ 1);
  EXPECT_NE(damage_of(flipped, "a", 1).find("section 'b' does not match its checksum"), std::string::npos);
  EXPECT_NE(damage_of(bytes.substr(0, bytes.size() - 1), "a", 1).find("it ends early"), std::string::npos);
  // The checksum covers a section's body, not its version: a version of 2 whose bit flipped
  // to 0 is damage, not the oldest format.
  std::string zero = bytes;
  // (section a: name length 8, "a", version 4, length 8, checksum 8, body 8; then b's name)
  const std::size_t b_version = 37 + 8 + 1;
  ASSERT_EQ(zero[b_version], '\x02');
  zero[b_version] = '\0';
  EXPECT_NE(damage_of(zero, "b", 2).find("section 'b' of version 0"), std::string::npos);
}

// A name is not under any checksum: a flipped bit in it is caught by the names a build knows.
TEST(SectionTable, RefusesASectionOfAnUnknownName) {
  std::string bytes = two_sections();
  BinaryReader in(bytes, "f");
  const std::array<std::string_view, 2> known{"a", "b"};
  EXPECT_NO_THROW(SectionTable(in).expect_known(known));
  bytes[37 + 8] = 'c';  // section b's name (after section a, as above)
  BinaryReader renamed(bytes, "f");
  try {
    SectionTable(renamed).expect_known(known);
    FAIL() << "a section of an unknown name passed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("damaged checkpoint (a section of unknown name 'c')"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace bushel::io
