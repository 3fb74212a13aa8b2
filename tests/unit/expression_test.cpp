#include "bushel/units/expression.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <string>

#include "bushel/core/input_error.hpp"

namespace bushel::units {
namespace {

const std::map<std::string, Quantity> names = {{"h", {0.1016, dim::length}},
                                               {"gap", {0.0508, dim::length}},
                                               {"scale", {0.5, dim::dimensionless}},
                                               {"fill.cup.mass", {0.2, dim::mass}},
                                               {"t", {2.0, dim::time}}};

Quantity eval(const std::string& text) {
  return evaluate(text, [](const std::string& n) {
    const auto it = names.find(n);
    if (it == names.end()) throw InputError("unknown name '" + n + "'");
    return it->second;
  });
}

std::string error_of(const std::string& text) {
  try {
    eval(text);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << text;
  return "";
}

TEST(Expression, ArithmeticFollowsPrecedenceAndParentheses) {
  EXPECT_DOUBLE_EQ(eval("1 + 2 * 3").value, 7.0);
  EXPECT_DOUBLE_EQ(eval("(1 + 2) * 3").value, 9.0);
  EXPECT_DOUBLE_EQ(eval("8 / 4 / 2").value, 1.0);  // left to right
  EXPECT_DOUBLE_EQ(eval("2 - 3 - 4").value, -5.0);
  EXPECT_DOUBLE_EQ(eval("-2 * -3").value, 6.0);
  EXPECT_DOUBLE_EQ(eval("1e-3 * 2").value, 2e-3);
}

TEST(Expression, UnitsConvertToSiAndDimensionsCombine) {
  const Quantity sum = eval("h + gap + 5.1 cm");
  EXPECT_NEAR(sum.value, 0.1016 + 0.0508 + 0.051, 1e-15);
  EXPECT_EQ(sum.dimension, dim::length);
  EXPECT_EQ(eval("h * scale").dimension, dim::length);
  EXPECT_EQ(eval("pi * (h/2) * (h/2) * h").dimension, dim::volume);
  const Quantity rho = eval("fill.cup.mass / (275.8 cm3)");
  EXPECT_EQ(rho.dimension, dim::density);
  EXPECT_NEAR(rho.value, 0.2 / 275.8e-6, 1e-9);
  EXPECT_EQ(eval("h / t").dimension, dim::velocity);
  EXPECT_EQ(eval("2 mm/s").dimension, dim::velocity);  // the longest unit
  EXPECT_NEAR(eval("10 mm/2").value, 5e-3, 1e-18);     // a unit, then a division
  EXPECT_NEAR(eval("50% * 2").value, 1.0, 1e-15);      // percent is a plain number
  EXPECT_NEAR(eval("sqrt(4 m2)").value, 2.0, 1e-15);
  EXPECT_EQ(eval("sqrt(4 m2)").dimension, dim::length);
  EXPECT_NEAR(eval("tan(60 deg)").value, std::sqrt(3.0), 1e-12);  // angles in radians
  EXPECT_NEAR(eval("(100 mm - 16.5 mm) / 2 * tan(60 deg)").value, 0.04175 * std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(eval("cos(pi)").value, -1.0, 1e-15);
  EXPECT_NEAR(eval("abs(-3 kPa)").value, 3000.0, 1e-12);
}

TEST(Expression, ErrorsNameTheExpressionAndTheProblem) {
  EXPECT_NE(error_of("h + t").find("in the expression 'h + t': cannot add a length and a time"), std::string::npos);
  EXPECT_NE(error_of("h - 2").find("cannot subtract a length and a dimensionless number"), std::string::npos);
  EXPECT_NE(error_of("h / 0").find("division by zero"), std::string::npos);
  EXPECT_NE(error_of("(h + gap").find("without its ')'"), std::string::npos);
  EXPECT_NE(error_of("h +").find("ends where a value was expected"), std::string::npos);
  EXPECT_NE(error_of("h gap").find("unexpected 'gap'"), std::string::npos);
  EXPECT_NE(error_of("hh * 2").find("unknown name 'hh'"), std::string::npos);
  EXPECT_NE(error_of("sqrt(h)").find("sqrt of a length has no unit"), std::string::npos);
  EXPECT_NE(error_of("sqrt(-1)").find("negative"), std::string::npos);
  EXPECT_NE(error_of("tan(h)").find("takes an angle, not a length"), std::string::npos);
  EXPECT_NE(error_of("log(2)").find("unknown function 'log'"), std::string::npos);
}

TEST(Expression, DepthLengthAndExponentsAreBounded) {
  // 64 levels of parentheses, functions or minuses are read; 65 are refused, never a stack
  // overflow, and so are 500,000 minuses or an exponent that would overflow.
  EXPECT_NEAR(eval(std::string(63, '(') + "h" + std::string(63, ')')).value, 0.1016, 1e-15);
  EXPECT_NE(error_of(std::string(65, '(') + "h" + std::string(65, ')')).find("nested more than 64 levels deep"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(65, '-') + "h").find("nested more than 64 levels deep"), std::string::npos);
  EXPECT_NE(error_of(std::string(500000, '-') + "h").find("longer than 4096 characters"), std::string::npos);
  // (the message quotes the start of a long expression, not all of it)
  EXPECT_LT(error_of(std::string(500000, '-') + "h").size(), 200u);
  std::string power = "h";
  for (int k = 1; k < 32; ++k) power += " * h";
  EXPECT_EQ(eval(power).dimension.length, 32);
  EXPECT_NE(error_of(power + " * h").find("a unit to a power beyond 32"), std::string::npos);
  EXPECT_NE(error_of("1e308 * 10").find("not a finite number"), std::string::npos);
}

TEST(Expression, QuantitiesParseAndFormatInSi) {
  EXPECT_NEAR(parse_quantity("101.6 mm").value, 0.1016, 1e-15);
  EXPECT_EQ(parse_quantity("101.6 mm").dimension, dim::length);
  EXPECT_EQ(parse_quantity("3").dimension, dim::dimensionless);
  EXPECT_THROW(parse_quantity("large"), InputError);
  EXPECT_THROW(parse_quantity("3 furlongs"), InputError);
  EXPECT_EQ(format_si({0.1524, dim::length}), "0.1524 m");
  EXPECT_EQ(format_si({826.1, dim::density}), "826.1 kg/m3");
  EXPECT_EQ(format_si({0.25, dim::dimensionless}), "0.25");
  EXPECT_EQ(si_symbol(dim::pressure), "Pa");
  EXPECT_THROW(si_symbol({1, 1, 0, 0}), InputError);
  // what is written reads back to the same value (12 significant digits)
  const Quantity q{std::numbers::pi * 1e-3, dim::length};
  EXPECT_NEAR(parse_quantity(format_si(q)).value, q.value, 1e-14);
}

}  // namespace
}  // namespace bushel::units
