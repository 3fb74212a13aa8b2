#pragma once
// Which runs of a table take part in an analysis: conditions on its columns such as
// "overflow_mass>0.001" (the cup filled) or "status==done". A designed experiment loses runs
// to failures the model cannot describe (a clogged funnel, a crashed run); the fit must leave
// them out, and say so, rather than bend to them.

#include <string>
#include <vector>

#include "bushel/io/csv.hpp"

namespace bushel::doe {

/// One condition: `column op value`. A value that reads as a number compares numerically
/// (and an empty or non-numeric cell fails the condition: a run without the value is left
/// out); any other value compares as text with == or !=.
struct RowCondition {
  enum class Op { less, less_equal, greater, greater_equal, equal, not_equal };
  std::string column;
  Op op = Op::equal;
  std::string value;
  bool numeric = false;
  double number = 0.0;  ///< `value` as a number when `numeric`
};

class RowFilter {
 public:
  /// Parses comma-separated conditions (all must hold); "" keeps every row. Throws
  /// InputError with the key `--where` for a condition without a column, operator or value,
  /// or a text value with an ordering operator.
  static RowFilter parse(const std::string& text);

  bool empty() const { return conditions_.empty(); }
  const std::string& text() const { return text_; }
  /// Throws InputError (file, column, did-you-mean) if `table` lacks a column the
  /// conditions name.
  void check_columns(const io::CsvTable& table) const;
  /// True if every condition holds for `row` of `table`.
  bool keeps(const io::CsvTable& table, const io::CsvRow& row) const;

 private:
  std::string text_;
  std::vector<RowCondition> conditions_;
};

}  // namespace bushel::doe
