/// libFuzzer target for data files: the bytes are a CSV file, parsed and checked as measured data
/// like a case's `data` file, and its text escaped for messages. Any crash, sanitizer report, hang
/// or unbounded memory use is a bug.

#include "lang/csv.hpp"
#include "lang/display_text.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

using namespace thermnet;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)lang::escape_for_display(text);
  (void)lang::excerpt_for_display(text);
  try {
    const lang::CsvTable t = lang::parse_csv(text, "fuzz.csv");
    // A parsed table is rectangular, starts with `time` and has strictly increasing times.
    for (const auto& column : t.cells)
      if (column.size() != t.rows()) std::abort();
    if (t.columns.empty() || t.columns[0] != "time") std::abort();
    for (std::size_t r = 1; r < t.rows(); ++r)
      if (!(t.time()[r] > t.time()[r - 1])) std::abort();
    if (t.rows() > 0 && lang::rows_after(t, t.time().back()) != 0) std::abort();
    lang::check_measured(t);
  } catch (const lang::CsvError& e) {
    (void)lang::escape_for_display(e.what());
  }
  return 0;
}
