#pragma once
/// Numbers as Fortran reads them in SINDA/FLUINT data: reals with an optional sign, digits with
/// an optional decimal point and an optional exponent marked E, D or Q (`1.0D3`, `1.E-2`, `+.5`,
/// `7`), and integers. What Fortran would reject (`1.0E`, `E5`, `1.2.3`, `0x10`, `1.0+3`) is not
/// a number.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace thermnet::importer {

/// Why a text is not a number.
enum class NumberProblem { none, malformed, out_of_range, underflow };

/// A parsed real, or why there is none.
struct RealResult {
  double value = 0;                            ///< the value (when problem is none)
  NumberProblem problem = NumberProblem::none; ///< none, malformed, too large or too small
};

/// Parses a whole field as a Fortran real (case-insensitive exponent letter E, D or Q).
RealResult parse_fortran_real(std::string_view text);

/// Parses a whole field as a Fortran integer (optional sign, decimal digits, fits in 64 bits).
std::optional<std::int64_t> parse_fortran_integer(std::string_view text);

/// The message for a field that is not a real: what Fortran accepts, or that it is too large.
std::string fortran_number_message(std::string_view text, NumberProblem problem);

/// The message for a number (of any format) whose magnitude is below the smallest double.
std::string underflow_message(std::string_view text);

} // namespace thermnet::importer
