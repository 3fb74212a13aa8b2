#include <gtest/gtest.h>

#include "bushel/core/input_error.hpp"

namespace bushel {
namespace {

TEST(InputError, ComposesFileLineAndKey) {
  const InputError e = InputError("expected a positive value").with_key("density").with_key("wheat").at("s.yaml", 12);
  EXPECT_STREQ(e.what(), "s.yaml:12: key 'wheat.density': expected a positive value");
  EXPECT_EQ(e.key(), "wheat.density");
  EXPECT_EQ(e.line(), 12);
}

TEST(InputError, InnermostSourceWins) {
  const InputError e = InputError("bad").at("inner.csv", 3).at("outer.yaml", 9);
  EXPECT_EQ(e.source(), "inner.csv");
  EXPECT_EQ(e.line(), 3);
}

TEST(InputError, IndexKeysJoinWithoutDot) {
  EXPECT_EQ(InputError("x").with_key("[2]").with_key("spheres").key(), "spheres[2]");
  EXPECT_STREQ(InputError("plain").what(), "plain");
}

}  // namespace
}  // namespace bushel
