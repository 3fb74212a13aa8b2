#pragma once
// A small reader for the comma-separated tables bushel ships and reads (particle templates,
// published data): a header row, then rows of fields. Every row keeps its line number so
// that errors point at the place in the file.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace bushel::io {

/// The most bytes `read_text_file` reads unless told otherwise: 1 GiB, above any mesh or
/// table bushel reads, below what would exhaust a machine's memory.
inline constexpr std::size_t max_file_bytes = std::size_t{1} << 30;

/// The whole content of a file; throws InputError naming the path if it cannot be read, is
/// a folder, or holds more than `limit` bytes (a device such as /dev/zero never ends).
std::string read_text_file(const std::string& path, std::size_t limit = max_file_bytes);

struct CsvRow {
  int line = 0;                     ///< 1-based line number in the source
  std::vector<std::string> fields;  ///< trimmed fields, as many as the header has
};

class CsvTable {
 public:
  /// Parses `text`; `source` names it in errors. Blank lines and lines starting with '#'
  /// are skipped. Throws InputError for a row whose field count differs from the header.
  static CsvTable parse(std::string_view text, std::string source);
  /// Reads and parses a file; throws InputError if it cannot be read.
  static CsvTable read(const std::string& path);

  const std::string& source() const { return source_; }
  const std::vector<std::string>& header() const { return header_; }
  const std::vector<CsvRow>& rows() const { return rows_; }

  /// Index of a column; throws InputError naming the file and the columns it has.
  std::size_t column(std::string_view name) const;
  /// True if the header has this column.
  bool has_column(std::string_view name) const;
  /// The field of `row` in `column` as a number; throws InputError with file, line and column.
  double number(const CsvRow& row, std::size_t column) const;

 private:
  std::string source_;
  std::vector<std::string> header_;
  std::vector<CsvRow> rows_;
};

}  // namespace bushel::io
