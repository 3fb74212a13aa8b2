// Base64 against the test vectors of RFC 4648 (section 10), and bytes of every value.
#include <gtest/gtest.h>

#include <string>

#include "bushel/io/base64.hpp"

namespace bushel::io {
namespace {

TEST(Base64, MatchesTheRfcVectors) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
}

TEST(Base64, EncodesEveryByteValue) {
  EXPECT_EQ(base64(std::string("\x00\xff\x80", 3)), "AP+A");
  EXPECT_EQ(base64(std::string("\xfb\xff", 2)), "+/8=");
  std::string all;
  for (int b = 0; b < 256; ++b) all += static_cast<char>(b);
  const std::string text = base64(all);
  EXPECT_EQ(text.size(), 344u);  // 4 ceil(256 / 3)
  EXPECT_EQ(text.substr(0, 8), "AAECAwQF");
  EXPECT_EQ(text.substr(text.size() - 8), "/P3+/w==");
}

}  // namespace
}  // namespace bushel::io
