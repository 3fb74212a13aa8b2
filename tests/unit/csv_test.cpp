#include <gtest/gtest.h>

#include "bushel/core/input_error.hpp"
#include "bushel/io/csv.hpp"

namespace bushel::io {
namespace {

TEST(Csv, ParsesRowsWithLineNumbers) {
  const CsvTable t = CsvTable::parse("# comment\na,b\n1, 2\n\n3,4\n", "t.csv");
  ASSERT_EQ(t.rows().size(), 2u);
  EXPECT_EQ(t.rows()[0].line, 3);
  EXPECT_EQ(t.rows()[1].line, 5);
  EXPECT_EQ(t.number(t.rows()[1], t.column("b")), 4.0);
}

TEST(Csv, ErrorsPointAtFileLineAndColumn) {
  try {
    const CsvTable t = CsvTable::parse("a,b\n1,x\n", "t.csv");
    t.number(t.rows()[0], 1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "t.csv:2: key 'b': expected a number, got 'x'");
  }
  EXPECT_THROW(CsvTable::parse("a,b\n1,2,3\n", "t.csv"), InputError);
  EXPECT_THROW(CsvTable::parse("", "t.csv"), InputError);
  EXPECT_THROW(CsvTable::read("/nonexistent/file.csv"), InputError);
  try {
    CsvTable::parse("radius_mm\n1\n", "t.csv").column("radius_m");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'radius_mm'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bushel::io
