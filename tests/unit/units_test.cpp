#include <gtest/gtest.h>

#include <numbers>

#include "bushel/core/input_error.hpp"
#include "bushel/units/units.hpp"

namespace bushel::units {
namespace {

TEST(Units, ParsesEverySuffixTheScenariosUse) {
  EXPECT_DOUBLE_EQ(parse("6.12mm", dim::length), 6.12e-3);
  EXPECT_DOUBLE_EQ(parse("1.5 m", dim::length), 1.5);
  EXPECT_DOUBLE_EQ(parse("0.0346g", dim::mass), 0.0346e-3);
  EXPECT_DOUBLE_EQ(parse("1.1kg", dim::mass), 1.1);
  EXPECT_DOUBLE_EQ(parse("1kg/s", dim::mass_flow), 1.0);
  EXPECT_DOUBLE_EQ(parse("138kPa", dim::pressure), 138e3);
  EXPECT_DOUBLE_EQ(parse("10 Pa", dim::pressure), 10.0);
  EXPECT_DOUBLE_EQ(parse("22.4MPa", dim::pressure), 22.4e6);
  EXPECT_DOUBLE_EQ(parse("37GPa", dim::pressure), 37e9);
  EXPECT_DOUBLE_EQ(parse("180deg", dim::angle), std::numbers::pi);
  EXPECT_DOUBLE_EQ(parse("7.85rad/s", dim::angular_velocity), 7.85);
  EXPECT_DOUBLE_EQ(parse("18s", dim::time), 18.0);
  EXPECT_DOUBLE_EQ(parse("0.5ms", dim::time), 0.5e-3);
  EXPECT_DOUBLE_EQ(parse("1373kg/m3", dim::density), 1373.0);
  EXPECT_DOUBLE_EQ(parse("275.8cm3", dim::volume), 275.8e-6);
  EXPECT_DOUBLE_EQ(parse("4.33Hz", dim::frequency), 4.33);
  EXPECT_DOUBLE_EQ(parse("-9.81m/s2", dim::acceleration), -9.81);
  EXPECT_DOUBLE_EQ(parse("+2e-3 m", dim::length), 2e-3);
}

TEST(Units, PoundsPerBushelMatchesTheStudysFactor) {
  // docs/wheat.md: 1 lb/bu = 12.8719 kg/m3.
  EXPECT_NEAR(parse("1lb/bu", dim::density), 12.8719, 1e-4);
  EXPECT_NEAR(to_unit(parse("60lb/bu", dim::density), "lb/bu"), 60.0, 1e-12);
  EXPECT_NEAR(to_unit(1101.22e-6, "bu"), 1.0 / 32.0, 1e-4);  // one quart is a 32nd of a bushel
}

TEST(Units, DimensionlessAcceptsBareNumbersAndPercent) {
  EXPECT_DOUBLE_EQ(parse("0.22", dim::dimensionless), 0.22);
  EXPECT_DOUBLE_EQ(parse("12%", dim::dimensionless), 0.12);
}

void expect_error(std::string_view text, Dimension d, const std::string& fragment) {
  try {
    parse(text, d);
    FAIL() << "no error for '" << text << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Units, RejectsMissingWrongAndUnknownUnits) {
  expect_error("6.12", dim::length, "the unit is missing");
  expect_error("6.12", dim::length, "expected a length with a unit (m, cm, mm");
  expect_error("6.12g", dim::length, "'g' is a unit of mass");
  expect_error("10kpa", dim::pressure, "did you mean 'kPa'");
  expect_error("7.85Hz", dim::angular_velocity, "'Hz' is a unit of frequency");
  expect_error("mm", dim::length, "got 'mm'");
  expect_error("", dim::length, "expected a length");
  expect_error("1.2.3mm", dim::length, "unknown unit");
  expect_error("nanmm", dim::length, "expected a length");
}

TEST(Units, PlainNumbersRejectTrailingText) {
  EXPECT_DOUBLE_EQ(parse_number(" 3.5 "), 3.5);
  EXPECT_THROW(parse_number("3.5mm"), InputError);
  EXPECT_THROW(parse_number("abc"), InputError);
}

TEST(Units, EverySymbolIsUniqueAndNamed) {
  const auto& table = known_units();
  for (std::size_t i = 0; i < table.size(); ++i) {
    EXPECT_EQ(dimension_name(table[i].dimension).find("quantity of dimension"), std::string::npos) << table[i].symbol;
    for (std::size_t j = i + 1; j < table.size(); ++j) EXPECT_NE(table[i].symbol, table[j].symbol);
  }
}

}  // namespace
}  // namespace bushel::units
