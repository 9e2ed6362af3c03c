#include "lang/csv.hpp"

#include "lang/display_text.hpp"
#include "lang/source.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace thermnet::lang {
namespace {

std::string trim(std::string_view s) {
  auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  auto e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

/// Splits a row at its commas. A field in double quotes may hold commas (`""` is a quote), and
/// a comma inside square brackets does not split either, so a header may name `p[3,7]` as it is
/// written or quoted, as spreadsheets write it.
std::vector<std::string> split(std::string_view line) {
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false, was_quoted = false;
  int brackets = 0;
  auto finish = [&] {
    fields.push_back(was_quoted ? field : trim(field));
    field.clear();
    was_quoted = false;
    brackets = 0;
  };
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"' && trim(field).empty()) {
      field.clear();
      quoted = was_quoted = true;
    } else if (c == ',' && brackets == 0) {
      finish();
    } else if (!was_quoted) {
      brackets += c == '[' ? 1 : c == ']' && brackets > 0 ? -1 : 0;
      field += c;
    }
  }
  finish();
  return fields;
}

bool parse_number(const std::string& s, double& out) {
  if (s.empty()) return false;
  const char* b = s.data();
  if (*b == '+') ++b;
  auto [p, ec] = std::from_chars(b, s.data() + s.size(), out);
  return ec == std::errc() && p == s.data() + s.size();
}

bool is_missing(const std::string& s) {
  if (s.empty()) return true;
  std::string l(s);
  std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::tolower(c); });
  return l == "nan" || l == "na";
}

/// A byte order mark, written first by some spreadsheet programs; it is not part of the header.
constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

/// Fails when a header of one field separates its columns with ';' (a spreadsheet export with a
/// locale whose decimal separator is ',').
void reject_semicolons(const std::vector<std::string>& header, const std::string& path,
                       std::size_t line_no) {
  if (header.size() != 1) return;
  const auto semicolon = header[0].find(';');
  if (semicolon == std::string::npos) return;
  throw CsvError(path, line_no, 1,
                 fmt::format("the header separates its columns with ';' (at character {}); "
                             "thermnet reads comma-separated values with '.' as the decimal "
                             "point: export the file with ',' as the separator",
                             semicolon + 1));
}

} // namespace

CsvError::CsvError(const std::string& path, std::size_t row_, std::size_t column_,
                   const std::string& msg)
    : std::runtime_error(row_ == 0      ? fmt::format("{}: {}", path, msg)
                         : column_ == 0 ? fmt::format("{}:{}: {}", path, row_, msg)
                                        : fmt::format("{}:{}:{}: {}", path, row_, column_, msg)),
      row(row_), column(column_) {}

int CsvTable::column_index(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  return -1;
}

CsvTable parse_csv(const std::string& text, const std::string& path) {
  CsvTable t;
  t.path = path;
  std::size_t pos = std::string_view(text).starts_with(kUtf8Bom) ? kUtf8Bom.size() : 0;
  std::size_t line_no = 0;
  bool header = true;
  while (pos <= text.size()) {
    auto nl = text.find('\n', pos);
    std::string_view line(text.data() + pos, (nl == std::string::npos ? text.size() : nl) - pos);
    pos = nl == std::string::npos ? text.size() + 1 : nl + 1;
    ++line_no;
    if (trim(line).empty()) continue;
    if (line.find('\0') != std::string_view::npos)
      throw CsvError(path, line_no, 0, "contains a NUL byte; is this a binary file?");
    auto fields = split(line);
    if (header) {
      header = false;
      reject_semicolons(fields, path, line_no);
      if (fields[0] != "time")
        throw CsvError(path, line_no, 1,
                       fmt::format("the first column must be 'time', found '{}'",
                                   excerpt_for_display(fields[0])));
      for (std::size_t c = 0; c < fields.size(); ++c) {
        if (fields[c].empty()) throw CsvError(path, line_no, c + 1, "empty column name");
        for (std::size_t k = 0; k < c; ++k)
          if (fields[k] == fields[c])
            throw CsvError(
                path, line_no, c + 1,
                fmt::format("column '{}' appears twice", excerpt_for_display(fields[c])));
      }
      t.columns = fields;
      t.cells.assign(fields.size(), {});
      continue;
    }
    if (fields.size() != t.columns.size())
      throw CsvError(path, line_no, 0,
                     fmt::format("row has {} fields, the header has {}{}", fields.size(),
                                 t.columns.size(),
                                 line.find(';') == std::string_view::npos
                                     ? ""
                                     : " (fields are separated by ',', not ';')"));
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double v = std::numeric_limits<double>::quiet_NaN();
      if (!is_missing(fields[c]) && !parse_number(fields[c], v))
        throw CsvError(path, line_no, c + 1,
                       fmt::format("'{}' is not a number{}", excerpt_for_display(fields[c]),
                                   fields[c].find(';') == std::string::npos
                                       ? ""
                                       : " (fields are separated by ',', not ';')"));
      if (!std::isnan(v) && !std::isfinite(v))
        throw CsvError(path, line_no, c + 1,
                       fmt::format("'{}' is not finite", excerpt_for_display(fields[c])));
      if (c == 0) {
        if (std::isnan(v)) throw CsvError(path, line_no, 1, "the time is missing");
        if (!t.cells[0].empty() && !(v > t.cells[0].back()))
          throw CsvError(path, line_no, 1,
                         fmt::format("time {:g} does not increase (previous row: {:g})", v,
                                     t.cells[0].back()));
      }
      t.cells[c].push_back(v);
    }
  }
  if (header) throw CsvError(path, 1, 0, "the file is empty; expected a header row 'time,...'");
  return t;
}

std::vector<std::string> csv_fields(std::string_view line) {
  return split(line);
}

bool csv_number(const std::string& field, double& out) {
  return parse_number(field, out);
}

CsvTable read_csv(const std::string& path) {
  std::string text;
  if (auto error = read_text_file(path, text)) throw CsvError(path, 0, 0, *error);
  return parse_csv(text, path);
}

std::size_t rows_after(const CsvTable& t, double end) {
  const std::vector<double>& time = t.time();
  const double last = end + 1e-9 * std::max(1.0, std::abs(end)); // the round-off of `end`
  return static_cast<std::size_t>(time.end() - std::upper_bound(time.begin(), time.end(), last));
}

void check_measured(const CsvTable& t) {
  const std::vector<double>& time = t.time();
  for (std::size_t r = 0; r < time.size(); ++r)
    if (time[r] < 0.0)
      // Rows are counted from the header (row 1); blank lines, if any, are not counted.
      throw CsvError(t.path, r + 2, 1,
                     fmt::format("time {:g} is negative; simulations start at 0", time[r]));
  for (std::size_t c = 1; c < t.cells.size(); ++c)
    for (double v : t.cells[c])
      if (!std::isnan(v)) return;
  throw CsvError(t.path, 1, 0,
                 "no measured value: the file has no cell with a number below its header");
}

} // namespace thermnet::lang
