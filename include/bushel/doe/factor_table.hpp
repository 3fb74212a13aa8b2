#pragma once
// A table of runs (CSV: factor columns and response columns) read for analysis, with each
// factor coded to -1 at its low and +1 at its high level.

#include <Eigen/Dense>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bushel/doe/row_filter.hpp"

namespace bushel::doe {

/// A factor and its two levels in physical units.
struct Factor {
  std::string name;
  double low = -1.0, high = 1.0;
  double code(double value) const { return (value - 0.5 * (low + high)) / (0.5 * (high - low)); }
  double decode(double coded) const { return 0.5 * (low + high) + coded * 0.5 * (high - low); }
};

struct FactorTable {
  std::vector<Factor> factors;
  Eigen::MatrixXd coded;            ///< runs x factors
  Eigen::VectorXd response;         ///< one per run
  std::vector<int> blocks;          ///< block label per run (empty without a block column)
  std::vector<int> excluded_lines;  ///< CSV lines of the rows `where` left out
};

/// Reads `path`; `factors` name columns, `response` a column, `block_column` (if not empty)
/// a column of integer block labels; only the rows that `where` keeps count. A factor's
/// levels are those in `levels` (name -> low, high) or else its smallest and largest value
/// among the kept rows. Throws InputError naming the file, line and column for a missing
/// column, a cell that is not a number, a factor that does not vary, or no row left.
FactorTable read_factor_table(const std::string& path, const std::vector<std::string>& factors,
                              const std::string& response,
                              const std::map<std::string, std::pair<double, double>>& levels = {},
                              const std::string& block_column = "", const RowFilter& where = {});

}  // namespace bushel::doe
