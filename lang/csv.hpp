#pragma once
/// Reading measured/simulated data files: a header row, a `time` column, numeric cells, missing
/// values.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::lang {

/// A problem in a CSV file at a 1-based row (line) and column (field).
struct CsvError : std::runtime_error {
  /// Builds "path:row:column: message".
  CsvError(const std::string& path, std::size_t row_, std::size_t column_, const std::string& msg);
  std::size_t row;    ///< 1-based line of the file
  std::size_t column; ///< 1-based field index (0 when the whole row is wrong)
};

/// A numeric table: the first column is time in s, missing cells are NaN.
struct CsvTable {
  std::string path;                       ///< file it was read from
  std::vector<std::string> columns;       ///< header names, columns[0] == "time"
  std::vector<std::vector<double>> cells; ///< cells[column][row]
  /// Number of data rows.
  std::size_t rows() const { return cells.empty() ? 0 : cells[0].size(); }
  /// Index of a column by name, or -1.
  int column_index(const std::string& name) const;
  /// The time column.
  const std::vector<double>& time() const { return cells.at(0); }
};

/// Parses CSV text (a leading UTF-8 byte order mark is skipped; ';' separators are refused with
/// a hint); rows must have increasing time; empty cells and `nan` are missing (NaN).
CsvTable parse_csv(const std::string& text, const std::string& path);
/// Reads and parses a CSV file; throws CsvError (row 0 when the file cannot be read).
CsvTable read_csv(const std::string& path);
/// The number of rows whose time is after `end` (s; beyond its round-off, 1e-9 relative): the
/// rows a case of that duration does not use.
std::size_t rows_after(const CsvTable& t, double end);
/// Splits one CSV row into its fields (trimmed; a quoted field or one in square brackets may hold
/// commas), as data files are split.
std::vector<std::string> csv_fields(std::string_view line);
/// Parses a whole field as a number (a leading '+' allowed); false when it is not one.
bool csv_number(const std::string& field, double& out);
/// Checks a table as measured data (no negative time, at least one value); throws CsvError.
void check_measured(const CsvTable& t);

} // namespace thermnet::lang
