/// libFuzzer target for data files: the bytes are a CSV file, parsed and checked as measured data
/// like a case's `data` file in the default layout and in the layouts test campaigns record
/// (another time column anywhere in the row, minutes or hours, UNIX seconds or nanoseconds, ISO
/// dates; `;`, tab and `|` separators), and its text escaped for messages; the first line is also
/// read as the unit of a `time = "COLUMN" [UNIT]` option. Any crash, sanitizer report, hang or
/// unbounded memory use is a bug.

#include "lang/csv.hpp"
#include "lang/display_text.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

using namespace thermnet;

namespace {

/// A layout with its time column, its unit or format as written in a model, and its separator.
lang::CsvLayout layout(const char* column, bool first, const char* unit, char separator) {
  lang::CsvLayout l;
  l.time_column = column;
  l.time_first = first;
  l.separator = separator;
  if (lang::parse_time_format(unit, l)) std::abort(); // every unit here is valid
  return l;
}

/// Parses `text` in layout `l` and checks what a parsed table promises.
void parse_in(const std::string& text, const lang::CsvLayout& l) {
  try {
    const lang::CsvTable t = lang::parse_csv(text, "fuzz.csv", l);
    // A parsed table is rectangular, starts with the time column and has strictly increasing
    // times; every column but the time has a field in the file.
    for (const auto& column : t.cells)
      if (column.size() != t.rows()) std::abort();
    if (t.columns.empty() || t.columns[0] != l.time_column) std::abort();
    if (t.file_columns.size() != t.columns.size() || t.lines.size() != t.rows()) std::abort();
    if (t.absolute_time != l.absolute()) std::abort();
    for (std::size_t r = 1; r < t.rows(); ++r)
      if (!(t.time()[r] > t.time()[r - 1])) std::abort();
    if (t.rows() > 0 && lang::rows_after(t, t.time().back()) != 0) std::abort();
    for (std::size_t c = 0; c < t.columns.size(); ++c) {
      (void)t.column_index(t.columns[c]);
      try {
        t.check_numbers(c); // a bad cell or an on/off word is reported at its row and column
      } catch (const lang::CsvError& e) {
        if (e.row == 0 || e.column == 0) std::abort();
      }
    }
    lang::check_measured(t);
  } catch (const lang::CsvError& e) {
    (void)lang::escape_for_display(e.what());
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)lang::escape_for_display(text);
  (void)lang::excerpt_for_display(text);
  // The first line as a time unit or format (`min`, `unix ns`, `iso`, or anything).
  {
    lang::CsvLayout l;
    (void)lang::parse_time_format(text.substr(0, text.find('\n')), l);
  }
  static const lang::CsvLayout layouts[] = {
      lang::CsvLayout{},                     // time,... in seconds
      layout("Time", false, "h", ';'),       // FlexHouse: t;Ta;...;yTi in hours
      layout("time", true, "unix s", ','),   // the incubator
      layout("time", false, "unix ns", ','), // the incubator's lid experiment
      layout("when", false, "iso", '\t'),    // ISO dates, tab-separated
      layout("t", false, "min", '|'),        // minutes, anywhere in the row
  };
  for (const auto& l : layouts)
    parse_in(text, l);
  return 0;
}
