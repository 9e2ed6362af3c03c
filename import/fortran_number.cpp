#include "import/fortran_number.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

namespace thermnet::importer {

namespace {

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

} // namespace

RealResult parse_fortran_real(std::string_view text) {
  // sign? (digits [. digits?] | . digits) ([EeDdQq] sign? digits)?
  std::size_t i = 0;
  const std::size_t n = text.size();
  std::string normal;
  normal.reserve(n);
  if (i < n && (text[i] == '+' || text[i] == '-')) normal += text[i++];
  std::size_t mantissa_digits = 0;
  while (i < n && is_digit(text[i])) {
    normal += text[i++];
    ++mantissa_digits;
  }
  if (i < n && text[i] == '.') {
    normal += text[i++];
    while (i < n && is_digit(text[i])) {
      normal += text[i++];
      ++mantissa_digits;
    }
  }
  if (mantissa_digits == 0) return {0, NumberProblem::malformed};
  if (i < n) {
    const char e = text[i];
    if (e != 'e' && e != 'E' && e != 'd' && e != 'D' && e != 'q' && e != 'Q')
      return {0, NumberProblem::malformed};
    normal += 'e';
    ++i;
    if (i < n && (text[i] == '+' || text[i] == '-')) normal += text[i++];
    std::size_t exponent_digits = 0;
    while (i < n && is_digit(text[i])) {
      normal += text[i++];
      ++exponent_digits;
    }
    if (exponent_digits == 0 || i != n) return {0, NumberProblem::malformed};
  }
  // from_chars, which no locale changes, reads no leading '+'.
  const char* first = normal.data() + (normal[0] == '+' ? 1 : 0);
  const char* last = normal.data() + normal.size();
  double v = 0;
  auto [p, ec] = std::from_chars(first, last, v);
  if (ec == std::errc::result_out_of_range) {
    // Too small would be read as zero (a capacity or conductance gone without a word): an error,
    // as too large is.
    if (normal.find("e-") != std::string::npos) return {0, NumberProblem::underflow};
    return {0, NumberProblem::out_of_range};
  }
  if (ec != std::errc() || p != last) return {0, NumberProblem::malformed};
  if (!std::isfinite(v)) return {0, NumberProblem::out_of_range};
  return {v, NumberProblem::none};
}

std::optional<std::int64_t> parse_fortran_integer(std::string_view text) {
  std::size_t i = 0;
  if (!text.empty() && text[0] == '+') i = 1;
  if (i >= text.size()) return std::nullopt;
  std::int64_t v = 0;
  const char* first = text.data() + i;
  const char* last = text.data() + text.size();
  if (*first == '-' && i == 1) return std::nullopt; // "+-3"
  auto [p, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || p != last) return std::nullopt;
  return v;
}

std::string fortran_number_message(std::string_view text, NumberProblem problem) {
  const std::string shown = lang::excerpt_for_display(text);
  if (problem == NumberProblem::out_of_range)
    return fmt::format("'{}' is too large for a double-precision number", shown);
  if (problem == NumberProblem::underflow) return underflow_message(text);
  return fmt::format("'{}' is not a number Fortran reads (write e.g. 1.5, -2, 1.5E3, 1.0D-3); "
                     "expressions and registers are not translated",
                     shown);
}

std::string underflow_message(std::string_view text) {
  return fmt::format("'{}' underflows: its magnitude is below the smallest number (4.9e-324); "
                     "write 0 if it is meant",
                     lang::excerpt_for_display(text));
}

} // namespace thermnet::importer
