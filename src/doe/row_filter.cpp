#include "bushel/doe/row_filter.hpp"

#include <fmt/format.h>

#include <array>
#include <utility>

#include "bushel/core/input_error.hpp"
#include "bushel/units/units.hpp"

namespace bushel::doe {

namespace {

// Two-character operators first, so that ">=" is not read as ">" and "=0.1".
constexpr std::array<std::pair<const char*, RowCondition::Op>, 7> operators{{
    {">=", RowCondition::Op::greater_equal},
    {"<=", RowCondition::Op::less_equal},
    {"==", RowCondition::Op::equal},
    {"!=", RowCondition::Op::not_equal},
    {">", RowCondition::Op::greater},
    {"<", RowCondition::Op::less},
    {"=", RowCondition::Op::equal},
}};

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t"), last = s.find_last_not_of(" \t");
  return first == std::string::npos ? std::string() : s.substr(first, last - first + 1);
}

RowCondition parse_condition(const std::string& item) {
  for (const auto& [symbol, op] : operators) {
    const auto at = item.find(symbol);
    if (at == std::string::npos) continue;
    RowCondition c{trimmed(item.substr(0, at)), op, trimmed(item.substr(at + std::string(symbol).size()))};
    if (c.column.empty() || c.value.empty()) break;
    try {
      c.number = units::parse_number(c.value);
      c.numeric = true;
    } catch (const InputError&) {
      if (op != RowCondition::Op::equal && op != RowCondition::Op::not_equal) {
        throw InputError(
            fmt::format("expected a number after '{}' in '{}' (a plain number, in the table's units)", symbol, item))
            .with_key("--where");
      }
    }
    return c;
  }
  throw InputError(fmt::format("expected COLUMN OP VALUE with OP one of < <= > >= == !=, e.g. overflow_mass>0.001; "
                               "got '{}'",
                               item))
      .with_key("--where");
}

}  // namespace

RowFilter RowFilter::parse(const std::string& text) {
  RowFilter f;
  f.text_ = text;
  std::string item;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    if (i < text.size() && text[i] != ',') {
      item += text[i];
      continue;
    }
    if (!trimmed(item).empty()) f.conditions_.push_back(parse_condition(item));
    item.clear();
  }
  return f;
}

void RowFilter::check_columns(const io::CsvTable& table) const {
  for (const RowCondition& c : conditions_) {
    try {
      (void)table.column(c.column);
    } catch (const InputError& e) {
      throw e.with_key("--where");
    }
  }
}

bool RowFilter::keeps(const io::CsvTable& table, const io::CsvRow& row) const {
  for (const RowCondition& c : conditions_) {
    const std::string& cell = row.fields.at(table.column(c.column));
    if (!c.numeric) {
      if ((cell == c.value) != (c.op == RowCondition::Op::equal)) return false;
      continue;
    }
    double v = 0.0;
    try {
      v = units::parse_number(cell);
    } catch (const InputError&) {
      return false;  // no value: the run failed or did not measure it
    }
    bool holds = false;
    switch (c.op) {
      case RowCondition::Op::less:
        holds = v < c.number;
        break;
      case RowCondition::Op::less_equal:
        holds = v <= c.number;
        break;
      case RowCondition::Op::greater:
        holds = v > c.number;
        break;
      case RowCondition::Op::greater_equal:
        holds = v >= c.number;
        break;
      case RowCondition::Op::equal:
        holds = v == c.number;
        break;
      case RowCondition::Op::not_equal:
        holds = v != c.number;
        break;
    }
    if (!holds) return false;
  }
  return true;
}

}  // namespace bushel::doe
