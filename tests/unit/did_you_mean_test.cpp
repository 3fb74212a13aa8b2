#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bushel/core/did_you_mean.hpp"

namespace bushel {
namespace {

TEST(DidYouMean, EditDistanceAgreesWithHandCounts) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("large_5s", "large_5s"), 0u);
  EXPECT_EQ(edit_distance("lareg_5s", "large_5s"), 2u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
}

TEST(DidYouMean, SuggestsOnlyCloseNames) {
  const std::vector<std::string> names = {"large_5s", "medium_5s", "small_5s", "large_asg"};
  EXPECT_EQ(closest_match("large_5", names), "large_5s");
  EXPECT_EQ(closest_match("meduim_5s", names), "medium_5s");
  EXPECT_EQ(closest_match("banana", names), "");
  EXPECT_EQ(did_you_mean("smal_5s", names), " (did you mean 'small_5s'?)");
}

}  // namespace
}  // namespace bushel
