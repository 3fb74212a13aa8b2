#include "bushel/io/csv.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "bushel/core/did_you_mean.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/units/units.hpp"

namespace bushel::io {
namespace {

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

std::vector<std::string> split(std::string_view line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    out.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

CsvTable CsvTable::parse(std::string_view text, std::string source) {
  CsvTable table;
  table.source_ = std::move(source);
  int line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const auto nl = text.find('\n', pos);
    const std::string_view line = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    auto fields = split(t);
    if (table.header_.empty()) {
      table.header_ = std::move(fields);
      continue;
    }
    if (fields.size() != table.header_.size()) {
      throw InputError("expected " + std::to_string(table.header_.size()) + " comma-separated fields (" +
                       std::to_string(fields.size()) + " found)")
          .at(table.source_, line_no);
    }
    table.rows_.push_back({line_no, std::move(fields)});
  }
  if (table.header_.empty()) throw InputError("expected a header row, the file is empty").at(table.source_);
  return table;
}

std::string read_text_file(const std::string& path, std::size_t limit) {
  std::error_code ec;
  const auto type = std::filesystem::status(path, ec).type();
  if (type == std::filesystem::file_type::directory) throw InputError("expected a file, this is a folder").at(path);
  if (type == std::filesystem::file_type::character || type == std::filesystem::file_type::block) {
    throw InputError("expected a file, this is a device").at(path);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open the file for reading").at(path);
  // In blocks up to the limit, so that a device or pipe that never ends is an error, not an
  // exhausted memory.
  std::string text;
  std::array<char, 1 << 16> block{};
  while (in) {
    in.read(block.data(), block.size());
    const auto got = static_cast<std::size_t>(in.gcount());
    if (text.size() + got > limit) {
      const std::string most =
          limit >= (1u << 20) ? fmt::format("{} MiB", limit >> 20) : fmt::format("{} bytes", limit);
      throw InputError("the file is larger than bushel reads (" + most + " at most)").at(path);
    }
    text.append(block.data(), got);
  }
  if (in.bad()) throw InputError("cannot read the file").at(path);
  return text;
}

CsvTable CsvTable::read(const std::string& path) { return parse(read_text_file(path), path); }

bool CsvTable::has_column(std::string_view name) const {
  return std::find(header_.begin(), header_.end(), name) != header_.end();
}

std::size_t CsvTable::column(std::string_view name) const {
  const auto it = std::find(header_.begin(), header_.end(), name);
  if (it != header_.end()) return static_cast<std::size_t>(it - header_.begin());
  std::string columns;
  for (const auto& h : header_) columns += (columns.empty() ? "" : ",") + h;
  throw InputError("missing column '" + std::string(name) + "'" + did_you_mean(name, header_) +
                   "; the header has: " + columns)
      .at(source_, 1);
}

double CsvTable::number(const CsvRow& row, std::size_t column) const {
  try {
    return units::parse_number(row.fields.at(column));
  } catch (const InputError& e) {
    throw e.with_key(header_.at(column)).at(source_, row.line);
  }
}

}  // namespace bushel::io
