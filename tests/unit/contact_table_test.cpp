#include <gtest/gtest.h>

#include <vector>

#include "bushel/contact/contact_table.hpp"
#include "bushel/core/input_error.hpp"

namespace bushel {
namespace {

// The single-sphere wheat model (docs/wheat.md): per pair of size fractions for wheat-wheat,
// one set for wheat-steel.
ContactTable single_sphere_wheat() {
  ContactTable t({0.5, 0.5, 0.0});
  t.set("large", "large", {0.5, 0.172, 0.05});
  t.set("large", "medium", {0.1, 0.486, 0.05});
  t.set("medium", "medium", {0.1, 0.486, 0.05});
  for (const char* other : {"large", "medium", "small"}) t.set("small", other, {0.1, 0.500, 0.10});
  t.set("wheat", "steel", {0.33, 0.17, 0.02});
  return t;
}

TEST(ContactTable, TypePairsOverrideMaterialPairs) {
  const ContactTable t = single_sphere_wheat();
  const Species large{"large", "wheat"}, medium{"medium", "wheat"}, small{"small", "wheat"}, wall{"", "steel"};
  EXPECT_EQ(t.lookup(large, large), (ContactParameters{0.5, 0.172, 0.05}));
  EXPECT_EQ(t.lookup(medium, large), (ContactParameters{0.1, 0.486, 0.05}));
  EXPECT_EQ(t.lookup(large, small), (ContactParameters{0.1, 0.500, 0.10}));
  EXPECT_EQ(t.lookup(small, wall), (ContactParameters{0.33, 0.17, 0.02}));
  EXPECT_EQ(t.lookup(wall, medium), t.lookup(medium, wall));
}

TEST(ContactTable, FallsBackToDefaults) {
  const ContactTable t({0.4, 0.3, 0.01});
  EXPECT_EQ(t.lookup({"a", "m1"}, {"b", "m2"}), (ContactParameters{0.4, 0.3, 0.01}));
}

TEST(ContactTable, TypeMaterialMixAndAmbiguity) {
  ContactTable t;
  const Species lid{"lid", "steel"}, small{"small", "wheat"};
  t.set("small", "steel", {0.2, 0.2, 0.2});
  EXPECT_EQ(t.lookup(small, lid).restitution, 0.2);
  EXPECT_EQ(t.lookup(lid, small).restitution, 0.2);
  // A second mix (lid type with wheat material) that disagrees is ambiguous...
  t.set("wheat", "lid", {0.3, 0.3, 0.3});
  EXPECT_THROW(t.lookup(lid, small), InputError);
  // ...until the pair of types settles it.
  t.set("lid", "small", {0.9, 0.9, 0.9});
  EXPECT_EQ(t.lookup(lid, small).restitution, 0.9);
}

TEST(ContactTable, DenseTableMatchesLookups) {
  const ContactTable t = single_sphere_wheat();
  const std::vector<Species> s = {{"large", "wheat"}, {"medium", "wheat"}, {"small", "wheat"}, {"", "steel"}};
  const DenseContactTable d = t.resolve(s);
  ASSERT_EQ(d.size(), 4u);
  for (std::size_t i = 0; i < s.size(); ++i) {
    for (std::size_t j = 0; j < s.size(); ++j) {
      EXPECT_EQ(d(i, j), t.lookup(s[i], s[j]));
      EXPECT_EQ(d(i, j), d(j, i));
    }
  }
}

TEST(ContactTable, RejectsUnphysicalParameters) {
  ContactTable t;
  EXPECT_THROW(t.set("a", "b", {0.0, 0.3, 0.0}), InputError);
  EXPECT_THROW(t.set("a", "b", {1.2, 0.3, 0.0}), InputError);
  EXPECT_THROW(t.set("a", "b", {0.5, -0.1, 0.0}), InputError);
  try {
    t.set("a", "b", {0.5, 0.3, -1.0});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "a-b.rolling_friction");
  }
}

}  // namespace
}  // namespace bushel
