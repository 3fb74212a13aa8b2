#include "bushel/doe/factor_table.hpp"

#include <fmt/format.h>

#include <cmath>

#include "bushel/core/input_error.hpp"
#include "bushel/io/csv.hpp"

namespace bushel::doe {

FactorTable read_factor_table(const std::string& path, const std::vector<std::string>& factors,
                              const std::string& response,
                              const std::map<std::string, std::pair<double, double>>& levels,
                              const std::string& block_column, const RowFilter& where) {
  const io::CsvTable t = io::CsvTable::read(path);
  where.check_columns(t);
  FactorTable out;
  std::vector<io::CsvRow> rows;
  for (const io::CsvRow& row : t.rows()) {
    if (where.keeps(t, row)) {
      rows.push_back(row);
    } else {
      out.excluded_lines.push_back(row.line);
    }
  }
  const auto n = static_cast<Eigen::Index>(rows.size());
  if (n == 0) {
    throw InputError(
        where.empty() ? "expected rows of runs"
                      : fmt::format("expected rows of runs; --where {} left out all {}", where.text(), t.rows().size()))
        .at(path);
  }
  out.coded.resize(n, static_cast<Eigen::Index>(factors.size()));
  out.response.resize(n);
  auto column_values = [&](const std::string& name) {
    const std::size_t c = t.column(name);
    Eigen::VectorXd v(n);
    for (Eigen::Index r = 0; r < n; ++r) v(r) = t.number(rows[static_cast<std::size_t>(r)], c);
    return v;
  };
  for (std::size_t f = 0; f < factors.size(); ++f) {
    const Eigen::VectorXd raw = column_values(factors[f]);
    Factor factor{factors[f], raw.minCoeff(), raw.maxCoeff()};
    if (const auto it = levels.find(factors[f]); it != levels.end())
      factor.low = it->second.first, factor.high = it->second.second;
    if (!(factor.high != factor.low)) {
      throw InputError(fmt::format("expected two levels of factor {}, found only {}", factors[f], factor.low))
          .at(path)
          .with_key(factors[f]);
    }
    for (Eigen::Index r = 0; r < n; ++r) out.coded(r, static_cast<Eigen::Index>(f)) = factor.code(raw(r));
    out.factors.push_back(factor);
  }
  out.response = column_values(response);
  if (!block_column.empty()) {
    const std::size_t c = t.column(block_column);
    for (const io::CsvRow& row : rows) {
      const double b = t.number(row, c);
      if (b != std::round(b)) {
        throw InputError(fmt::format("expected an integer block label, got {}", b))
            .at(path, row.line)
            .with_key(block_column);
      }
      out.blocks.push_back(static_cast<int>(b));
    }
  }
  return out;
}

}  // namespace bushel::doe
