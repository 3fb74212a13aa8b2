#include "bushel/doe/row_filter.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "bushel/core/input_error.hpp"
#include "bushel/doe/factor_table.hpp"
#include "temp_dir_test.hpp"

namespace bushel::doe {
namespace {

// Runs of a campaign: two filled the cup, one clogged (no overflow), one failed (no values).
constexpr const char* runs_csv =
    "std_order,fr_ww,bulk_density,overflow_mass,status\n"
    "1,0,840,0.024,done\n"
    "2,0.1,462,0,done\n"
    "3,0.1,826,0.02,done\n"
    "4,0.05,,,failed\n";

std::vector<int> kept_lines(const RowFilter& f, const io::CsvTable& t) {
  std::vector<int> lines;
  for (const io::CsvRow& row : t.rows())
    if (f.keeps(t, row)) lines.push_back(row.line);
  return lines;
}

TEST(RowFilter, NumericConditionsLeaveOutRunsWithoutTheValue) {
  const io::CsvTable t = io::CsvTable::parse(runs_csv, "runs.csv");
  EXPECT_EQ(kept_lines(RowFilter::parse("overflow_mass>0.001"), t), (std::vector<int>{2, 4}));
  EXPECT_EQ(kept_lines(RowFilter::parse("overflow_mass>=0.02"), t), (std::vector<int>{2, 4}));
  EXPECT_EQ(kept_lines(RowFilter::parse("overflow_mass<0.02"), t), (std::vector<int>{3}));
  EXPECT_EQ(kept_lines(RowFilter::parse("overflow_mass<=0.02"), t), (std::vector<int>{3, 4}));
  EXPECT_EQ(kept_lines(RowFilter::parse("fr_ww == 0.1"), t), (std::vector<int>{3, 4}));
  EXPECT_EQ(kept_lines(RowFilter::parse("fr_ww!=0.1"), t), (std::vector<int>{2, 5}));
  EXPECT_EQ(kept_lines(RowFilter::parse("fr_ww>-1"), t), (std::vector<int>{2, 3, 4, 5}));
  // all conditions must hold; blanks between items are ignored
  EXPECT_EQ(kept_lines(RowFilter::parse("overflow_mass>0, fr_ww=0.1 ,"), t), (std::vector<int>{4}));
  EXPECT_EQ(kept_lines(RowFilter::parse(""), t), (std::vector<int>{2, 3, 4, 5}));
  EXPECT_TRUE(RowFilter::parse(" ").empty());
}

TEST(RowFilter, TextConditionsCompareCells) {
  const io::CsvTable t = io::CsvTable::parse(runs_csv, "runs.csv");
  EXPECT_EQ(kept_lines(RowFilter::parse("status==done"), t), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(kept_lines(RowFilter::parse("status!=done"), t), (std::vector<int>{5}));
}

TEST(RowFilter, BadConditionsAreClearErrors) {
  auto message = [](const std::string& text) {
    try {
      const io::CsvTable t = io::CsvTable::parse(runs_csv, "runs.csv");
      RowFilter::parse(text).check_columns(t);
    } catch (const InputError& e) {
      EXPECT_EQ(e.key().rfind("--where", 0), 0u) << e.what();
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("overflow_mass").find("expected COLUMN OP VALUE"), std::string::npos);
  EXPECT_NE(message(">0.1").find("expected COLUMN OP VALUE"), std::string::npos);
  EXPECT_NE(message("overflow_mass>").find("expected COLUMN OP VALUE"), std::string::npos);
  EXPECT_NE(message("status>done").find("expected a number after '>'"), std::string::npos);
  EXPECT_NE(message("overflow_mas>0").find("did you mean 'overflow_mass'"), std::string::npos);
}

class FilteredTable : public TempDirTest {};

TEST_F(FilteredTable, FitsOnlyTheKeptRunsAndNamesTheOthers) {
  const std::string file = path("runs.csv");
  std::ofstream(file) << runs_csv;
  // Without a filter the failed run's empty cell is an error with its line and column.
  try {
    (void)read_factor_table(file, {"fr_ww"}, "bulk_density");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 5);
    EXPECT_EQ(e.key(), "bulk_density");
  }
  const FactorTable t = read_factor_table(file, {"fr_ww"}, "bulk_density", {{"fr_ww", {0.0, 0.1}}}, "",
                                          RowFilter::parse("overflow_mass>0"));
  ASSERT_EQ(t.response.size(), 2);
  EXPECT_EQ(t.response(0), 840.0);
  EXPECT_EQ(t.response(1), 826.0);
  EXPECT_EQ(t.coded(0, 0), -1.0);  // coded against the design's levels, not the kept runs' range
  EXPECT_EQ(t.coded(1, 0), 1.0);
  EXPECT_EQ(t.excluded_lines, (std::vector<int>{3, 5}));
  try {
    (void)read_factor_table(file, {"fr_ww"}, "bulk_density", {}, "", RowFilter::parse("overflow_mass>1"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--where overflow_mass>1 left out all 4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bushel::doe
