#pragma once
/// Reading measured/simulated data files: a header row, a time column, numeric (or on/off) cells,
/// missing values; the layout of files as test campaigns record them (another time column, its
/// unit, UNIX or ISO time stamps, another separator).

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

namespace thermnet::lang {

/// A problem in a CSV file at a 1-based row (line) and column (field).
struct CsvError : std::runtime_error {
  /// Builds "path:row:column: message".
  CsvError(const std::string& path, std::size_t row_, std::size_t column_, const std::string& msg);
  std::size_t row;    ///< 1-based line of the file
  std::size_t column; ///< 1-based field index (0 when the whole row is wrong)
  std::string detail; ///< the message without the location
};

/// How the time column's values are written.
enum class TimeFormat {
  relative,  ///< a number of units (seconds unless a unit is given) from the case's start
  unix_time, ///< a UNIX time stamp (seconds, ms, us or ns since 1970-01-01 UTC)
  iso        ///< an ISO 8601 date and time (`2021-01-22T14:48:58.7Z`, `2021-01-22 14:48`)
};

/// Where a CSV file keeps its time and how its fields are separated.
struct CsvLayout {
  std::string time_column = "time";         ///< name of the time column
  bool time_first = true;                   ///< the time column must be the first (the default)
  TimeFormat format = TimeFormat::relative; ///< how times are written
  double time_scale = 1.0;                  ///< seconds per unit of a number (relative, unix)
  char separator = ',';                     ///< field separator
  /// True when times are absolute (UNIX or ISO): a case starts at a chosen epoch.
  bool absolute() const { return format != TimeFormat::relative; }
  /// Orders layouts (a key of the table cache).
  bool operator<(const CsvLayout& o) const {
    return std::tie(time_column, time_first, format, time_scale, separator) <
           std::tie(o.time_column, o.time_first, o.format, o.time_scale, o.separator);
  }
};

/// Parses a time unit or format as written in `time = "COLUMN" [UNIT]`: a time unit (`s`, `min`,
/// `h`, `day`, `ms`), `unix s|ms|us|ns` or `iso`; fills in the layout, or returns what is wrong.
std::optional<std::string> parse_time_format(std::string_view text, CsvLayout& layout);

/// A cell that is neither a number, a missing value nor an on/off word.
struct BadCell {
  std::size_t row = 0;    ///< 1-based line
  std::size_t column = 0; ///< 1-based field
  std::string text;       ///< the cell as written
};

/// A numeric table: the first column is the time in s (from 1970 for absolute layouts), missing
/// cells are NaN, on/off words (`True`/`False`, `on`/`off`, `yes`/`no`) are 1 and 0.
struct CsvTable {
  std::string path;                        ///< file it was read from
  std::vector<std::string> columns;        ///< header names, columns[0] the time column's
  std::vector<std::vector<double>> cells;  ///< cells[column][row]
  std::vector<std::size_t> file_columns;   ///< 1-based field of each column in the file
  std::vector<std::size_t> lines;          ///< 1-based line of each row
  std::vector<std::size_t> word_line;      ///< per column: line of its first on/off word (0: none)
  std::vector<std::optional<BadCell>> bad; ///< per column: its first cell that is not a value
  bool absolute_time = false;              ///< times are UNIX seconds (UNIX or ISO layout)
  /// Number of data rows.
  std::size_t rows() const { return cells.empty() ? 0 : cells[0].size(); }
  /// Index of a column by name, or -1.
  int column_index(const std::string& name) const;
  /// The time column.
  const std::vector<double>& time() const { return cells.at(0); }
  /// Throws the CsvError of the column's first cell that is not a value, if it has one.
  void check_column(std::size_t column) const;
  /// check_column(), and no on/off word either (a column of temperatures).
  void check_numbers(std::size_t column) const;

  /// The 1-based line of a row.
  std::size_t line_of(std::size_t row) const { return row < lines.size() ? lines[row] : row + 2; }
};

/// Parses CSV text (a leading UTF-8 byte order mark is skipped); rows must have increasing time;
/// empty cells and `nan` are missing (NaN). With the default layout, a header separated by ';' is
/// refused with a hint, and the first column must be `time`.
CsvTable parse_csv(const std::string& text, const std::string& path, const CsvLayout& layout = {});
/// Reads and parses a CSV file; throws CsvError (row 0 when the file cannot be read).
CsvTable read_csv(const std::string& path, const CsvLayout& layout = {});
/// The number of rows whose time is after `end` (s; beyond its round-off, 1e-9 relative): the
/// rows a case of that duration does not use.
std::size_t rows_after(const CsvTable& t, double end);
/// Splits one CSV row into its fields (trimmed; a quoted field or one in square brackets may hold
/// the separator), as data files are split.
std::vector<std::string> csv_fields(std::string_view line, char separator = ',');
/// Parses a whole field as a number (a leading '+' allowed); false when it is not one.
bool csv_number(const std::string& field, double& out);
/// Checks a table as measured data (no negative time, at least one value); throws CsvError.
void check_measured(const CsvTable& t);

} // namespace thermnet::lang
