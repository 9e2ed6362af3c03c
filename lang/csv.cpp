#include "lang/csv.hpp"

#include "lang/diagnostics.hpp"
#include "lang/display_text.hpp"
#include "lang/on_off_words.hpp"
#include "lang/source.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
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

/// Splits a row at its separators. A field in double quotes may hold the separator (`""` is a
/// quote), and a separator inside square brackets does not split either, so a header may name
/// `p[3,7]` as it is written or quoted, as spreadsheets write it.
std::vector<std::string> split(std::string_view line, char separator) {
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
    } else if (c == separator && brackets == 0) {
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

/// What is wrong with a field that parse_number() refuses: "'x' is not a number", or that it
/// overflows or underflows a double (1e400, 1e-400).
std::string number_problem(const std::string& s) {
  const char* b = s.c_str();
  if (*b == '+') ++b;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(b, &end);
  if (errno == ERANGE && end == s.c_str() + s.size()) {
    if (std::isinf(v))
      return fmt::format("'{}' overflows: its magnitude is above the largest number (1.8e308)",
                         excerpt_for_display(s));
    if (std::abs(v) < std::numeric_limits<double>::denorm_min())
      return fmt::format("'{}' underflows: its magnitude is below the smallest number (4.9e-324); "
                         "write 0 if it is meant",
                         excerpt_for_display(s));
  }
  if (end == s.c_str() + s.size() && !std::isfinite(v))
    return fmt::format("'{}' is not a finite number", excerpt_for_display(s));
  return fmt::format("'{}' is not a number", excerpt_for_display(s));
}

std::string lower(std::string_view s) {
  std::string l(s);
  std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::tolower(c); });
  return l;
}

bool is_missing(const std::string& s) {
  if (s.empty()) return true;
  const std::string l = lower(s);
  return l == "nan" || l == "na";
}

/// Days from 1970-01-01 to a date of the proleptic Gregorian calendar (H. Hinnant's algorithm).
long days_from_civil(long y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const long era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long>(doe) - 719468;
}

/// Days of a month of the proleptic Gregorian calendar.
long days_in_month(long y, long m) {
  static constexpr long days[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  return m == 2 && leap ? 29 : days[m - 1];
}

/// An ISO 8601 date and time (`2021-01-22`, `2021-01-22T14:48:58.72Z`, `2021-01-22 14:48+01:00`)
/// as seconds since 1970-01-01 UTC; a time without zone is taken as UTC. A well-formed stamp with
/// a field out of its range (2021-02-30, 25:00, +99:99) sets `why` to that field's problem.
std::optional<double> parse_iso_time(std::string_view s, std::string& why) {
  std::size_t i = 0;
  auto digits = [&](std::size_t n, long& out) {
    if (i + n > s.size()) return false;
    out = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const char c = s[i + k];
      if (c < '0' || c > '9') return false;
      out = out * 10 + (c - '0');
    }
    i += n;
    return true;
  };
  auto expect = [&](char c) {
    if (i < s.size() && s[i] == c) {
      ++i;
      return true;
    }
    return false;
  };
  long y = 0, mo = 0, d = 0, h = 0, mi = 0, sec = 0;
  if (!digits(4, y) || !expect('-') || !digits(2, mo) || !expect('-') || !digits(2, d))
    return std::nullopt;
  if (mo < 1 || mo > 12) {
    why = fmt::format("there is no month {}", mo);
    return std::nullopt;
  }
  if (d < 1 || d > days_in_month(y, mo)) {
    why = fmt::format("{:04}-{:02} has no day {} (it has {} days)", y, mo, d, days_in_month(y, mo));
    return std::nullopt;
  }
  double seconds = 0.0;
  if (i < s.size() && (s[i] == 'T' || s[i] == ' ')) {
    ++i;
    if (!digits(2, h) || !expect(':') || !digits(2, mi)) return std::nullopt;
    if (expect(':')) {
      if (!digits(2, sec)) return std::nullopt;
      if (i < s.size() && (s[i] == '.' || s[i] == ',')) {
        ++i;
        double scale = 0.1;
        const std::size_t from = i;
        while (i < s.size() && s[i] >= '0' && s[i] <= '9') {
          seconds += scale * (s[i] - '0');
          scale /= 10;
          ++i;
        }
        if (i == from) return std::nullopt;
      }
    }
    // 24:00 is the end of a day (ISO 8601), 60 s a leap second; nothing later.
    if (h > 24 || mi > 59 || sec > 60 || (h == 24 && (mi > 0 || sec > 0 || seconds > 0.0))) {
      why = "the time of day lies outside 00:00 .. 24:00";
      return std::nullopt;
    }
  }
  long zone = 0; // seconds east of UTC
  if (i < s.size()) {
    if (s[i] == 'Z') {
      ++i;
    } else if (s[i] == '+' || s[i] == '-') {
      const long sign = s[i] == '+' ? 1 : -1;
      ++i;
      long zh = 0, zm = 0;
      if (!digits(2, zh)) return std::nullopt;
      expect(':');
      if (i < s.size() && !digits(2, zm)) return std::nullopt;
      // Zones in use lie within -12:00 .. +14:00; minutes are minutes.
      if (zh > 14 || zm > 59) {
        why = "a time zone lies within -12:00 .. +14:00";
        return std::nullopt;
      }
      zone = sign * (zh * 3600 + zm * 60);
    }
  }
  if (i != s.size()) return std::nullopt;
  const long days = days_from_civil(y, static_cast<unsigned>(mo), static_cast<unsigned>(d));
  return static_cast<double>(days * 86400 + h * 3600 + mi * 60 + sec - zone) + seconds;
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

std::optional<double> on_off_word(const std::string& s) {
  const std::size_t space = s.find_last_of(" \t");
  const std::string l = lower(space == std::string::npos ? s : s.substr(space + 1));
  static const char* const on[] = {"true", "on", "yes", "open", "opened", "start", "started"};
  static const char* const off[] = {"false", "off", "no", "close", "closed", "stop", "stopped"};
  for (const char* w : on)
    if (l == w) return 1.0;
  for (const char* w : off)
    if (l == w) return 0.0;
  return std::nullopt;
}

CsvError::CsvError(const std::string& path, std::size_t row_, std::size_t column_,
                   const std::string& msg)
    : std::runtime_error(row_ == 0      ? fmt::format("{}: {}", path, msg)
                         : column_ == 0 ? fmt::format("{}:{}: {}", path, row_, msg)
                                        : fmt::format("{}:{}:{}: {}", path, row_, column_, msg)),
      row(row_), column(column_), detail(msg) {}

int CsvTable::column_index(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  return -1;
}

std::optional<std::string> parse_time_format(std::string_view text, CsvLayout& layout) {
  std::string t(trim(text));
  if (t == "iso") {
    layout.format = TimeFormat::iso;
    layout.time_scale = 1.0;
    return std::nullopt;
  }
  if (t.starts_with("unix")) {
    const std::string unit = trim(std::string_view(t).substr(4));
    static const std::pair<const char*, double> units[] = {
        {"s", 1.0}, {"ms", 1e-3}, {"us", 1e-6}, {"ns", 1e-9}};
    for (const auto& [name, scale] : units)
      if (unit == name) {
        layout.format = TimeFormat::unix_time;
        layout.time_scale = scale;
        return std::nullopt;
      }
    return fmt::format("UNIX time stamps are in 'unix s', 'unix ms', 'unix us' or 'unix ns', not "
                       "'{}'",
                       excerpt_for_display(t));
  }
  try {
    const Unit u = parse_unit(t);
    if (!(u.dim == dim::time))
      return fmt::format("'{}' is not a unit of time; write a time unit ([s], [min], [h], "
                         "[day]), [unix s] (or ms, us, ns) or [iso]",
                         excerpt_for_display(t));
    layout.format = TimeFormat::relative;
    layout.time_scale = u.scale;
    return std::nullopt;
  } catch (const UnitError& e) {
    return fmt::format("{}; the time is in a time unit ([s], [min], [h], [day]), [unix s] (or ms, "
                       "us, ns) or [iso]",
                       e.what());
  }
}

void CsvTable::check_column(std::size_t column) const {
  if (column >= bad.size() || !bad[column]) return;
  const BadCell& b = *bad[column];
  throw CsvError(path, b.row, b.column,
                 fmt::format("{}{}", number_problem(b.text),
                             b.text.find(';') == std::string::npos
                                 ? ""
                                 : " (fields are separated by ',', not ';')"));
}

void CsvTable::check_numbers(std::size_t column) const {
  check_column(column);
  if (column >= word_line.size() || word_line[column] == 0) return;
  throw CsvError(path, word_line[column], file_columns[column],
                 fmt::format("column '{}' holds on/off words (True/False), not temperatures",
                             excerpt_for_display(columns[column])));
}

CsvTable parse_csv(const std::string& text, const std::string& path, const CsvLayout& layout) {
  CsvTable t;
  t.path = path;
  t.absolute_time = layout.absolute();
  const char sep = layout.separator;
  const bool default_layout = layout.time_first && sep == ',';
  std::size_t pos = std::string_view(text).starts_with(kUtf8Bom) ? kUtf8Bom.size() : 0;
  std::size_t line_no = 0;
  bool header = true;
  std::size_t width = 0;              // fields per row
  std::size_t time_at = 0;            // the time column's field (0-based)
  std::vector<std::size_t> column_of; // file field -> table column
  while (pos <= text.size()) {
    auto nl = text.find('\n', pos);
    std::string_view line(text.data() + pos, (nl == std::string::npos ? text.size() : nl) - pos);
    pos = nl == std::string::npos ? text.size() + 1 : nl + 1;
    ++line_no;
    if (trim(line).empty()) continue;
    if (line.find('\0') != std::string_view::npos)
      throw CsvError(path, line_no, 0, "contains a NUL byte; is this a binary file?");
    auto fields = split(line, sep);
    if (header) {
      header = false;
      if (default_layout) reject_semicolons(fields, path, line_no);
      for (std::size_t c = 0; c < fields.size(); ++c) {
        if (fields[c].empty()) throw CsvError(path, line_no, c + 1, "empty column name");
        for (std::size_t k = 0; k < c; ++k)
          if (fields[k] == fields[c])
            throw CsvError(
                path, line_no, c + 1,
                fmt::format("column '{}' appears twice", excerpt_for_display(fields[c])));
      }
      if (layout.time_first) {
        if (fields[0] != layout.time_column)
          throw CsvError(path, line_no, 1,
                         fmt::format("the first column must be '{}', found '{}'",
                                     layout.time_column, excerpt_for_display(fields[0])));
      } else {
        auto it = std::find(fields.begin(), fields.end(), layout.time_column);
        if (it == fields.end()) {
          std::string msg =
              fmt::format("there is no time column '{}'", excerpt_for_display(layout.time_column));
          if (auto s = closest_match(layout.time_column, fields))
            msg += fmt::format(" (did you mean '{}'?)", excerpt_for_display(*s));
          throw CsvError(path, line_no, 0, msg);
        }
        time_at = static_cast<std::size_t>(it - fields.begin());
      }
      width = fields.size();
      column_of.assign(width, 0);
      t.columns.push_back(fields[time_at]);
      t.file_columns.push_back(time_at + 1);
      for (std::size_t c = 0; c < width; ++c) {
        if (c == time_at) continue;
        column_of[c] = t.columns.size();
        t.columns.push_back(fields[c]);
        t.file_columns.push_back(c + 1);
      }
      t.cells.assign(width, {});
      t.word_line.assign(width, 0);
      t.bad.assign(width, std::nullopt);
      continue;
    }
    if (fields.size() != width)
      throw CsvError(path, line_no, 0,
                     fmt::format("row has {} fields, the header has {}{}", fields.size(), width,
                                 default_layout && line.find(';') != std::string_view::npos
                                     ? " (fields are separated by ',', not ';')"
                                     : ""));
    // The time first: a row without one is an error of the whole file.
    const std::string& tf = fields[time_at];
    double time = std::numeric_limits<double>::quiet_NaN();
    if (is_missing(tf)) throw CsvError(path, line_no, time_at + 1, "the time is missing");
    if (layout.format == TimeFormat::iso) {
      std::string why;
      if (auto v = parse_iso_time(tf, why))
        time = *v;
      else if (!why.empty())
        throw CsvError(
            path, line_no, time_at + 1,
            fmt::format("'{}' is not a date and time: {}", excerpt_for_display(tf), why));
      else
        throw CsvError(path, line_no, time_at + 1,
                       fmt::format("'{}' is not an ISO 8601 date and time "
                                   "(2021-01-22T14:48:58Z)",
                                   excerpt_for_display(tf)));
    } else {
      if (!parse_number(tf, time))
        throw CsvError(path, line_no, time_at + 1,
                       fmt::format("{}{}", number_problem(tf),
                                   default_layout && tf.find(';') != std::string::npos
                                       ? " (fields are separated by ',', not ';')"
                                       : ""));
      if (!std::isfinite(time))
        throw CsvError(path, line_no, time_at + 1,
                       fmt::format("'{}' is not finite", excerpt_for_display(tf)));
      time *= layout.time_scale;
    }
    if (!t.cells[0].empty() && !(time > t.cells[0].back()))
      throw CsvError(path, line_no, time_at + 1,
                     fmt::format("time {:.10g} does not increase (previous row: {:.10g})",
                                 time / layout.time_scale, t.cells[0].back() / layout.time_scale));
    t.cells[0].push_back(time);
    t.lines.push_back(line_no);
    for (std::size_t c = 0; c < width; ++c) {
      if (c == time_at) continue;
      const std::size_t col = column_of[c];
      double v = std::numeric_limits<double>::quiet_NaN();
      if (!is_missing(fields[c]) && !parse_number(fields[c], v)) {
        if (auto w = on_off_word(fields[c])) {
          v = *w;
          if (t.word_line[col] == 0) t.word_line[col] = line_no;
        } else if (!t.bad[col]) {
          t.bad[col] = BadCell{line_no, c + 1, fields[c]};
        }
      } else if (!std::isnan(v) && !std::isfinite(v) && !t.bad[col]) {
        t.bad[col] = BadCell{line_no, c + 1, fields[c]};
        v = std::numeric_limits<double>::quiet_NaN();
      }
      t.cells[col].push_back(v);
    }
  }
  if (header)
    throw CsvError(
        path, 1, 0,
        fmt::format("the file is empty; expected a header row '{},...'", layout.time_column));
  t.cells.resize(t.columns.size());
  t.word_line.resize(t.columns.size());
  t.bad.resize(t.columns.size());
  return t;
}

std::vector<std::string> csv_fields(std::string_view line, char separator) {
  return split(line, separator);
}

bool csv_number(const std::string& field, double& out) {
  return parse_number(field, out);
}

CsvTable read_csv(const std::string& path, const CsvLayout& layout) {
  std::string text;
  if (auto error = read_text_file(path, text)) throw CsvError(path, 0, 0, *error);
  return parse_csv(text, path, layout);
}

std::size_t rows_after(const CsvTable& t, double end) {
  const std::vector<double>& time = t.time();
  const double last = end + 1e-9 * std::max(1.0, std::abs(end)); // the round-off of `end`
  return static_cast<std::size_t>(time.end() - std::upper_bound(time.begin(), time.end(), last));
}

void check_measured(const CsvTable& t) {
  const std::vector<double>& time = t.time();
  if (!t.absolute_time)
    for (std::size_t r = 0; r < time.size(); ++r)
      if (time[r] < 0.0)
        throw CsvError(t.path, t.line_of(r), t.file_columns[0],
                       fmt::format("time {:g} is negative; simulations start at 0", time[r]));
  for (std::size_t c = 1; c < t.cells.size(); ++c)
    for (double v : t.cells[c])
      if (!std::isnan(v)) return;
  throw CsvError(t.path, 1, 0,
                 "no measured value: the file has no cell with a number below its header");
}

} // namespace thermnet::lang
