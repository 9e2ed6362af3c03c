#pragma once
/// Numbers as SPICE reads them: a decimal number with an optional exponent, then an optional
/// scale suffix (f p n u m k meg g t mil, any case) and unit letters SPICE ignores (`10uF`,
/// `2kOhm`, `1MEG`). `1F` is 1e-15 (femto), as in every SPICE.

#include <cstddef>
#include <optional>
#include <string_view>

namespace thermnet::importer::spice {

/// A number read from the start of a text.
struct SpiceNumber {
  double value = 0;         ///< the value with its suffix applied
  std::size_t length = 0;   ///< characters read (the number, its suffix and unit letters)
  bool femto_alone = false; ///< the suffix was a lone `f`/`F` (a femto a reader may take for farad)
  bool underflow = false;   ///< not 0, but below the smallest double (`1e-400`): value is 0
};

/// Reads a number at the start of `text` (letters after it are its suffix and unit); nothing
/// when `text` does not start with a number.
std::optional<SpiceNumber> read_spice_number(std::string_view text);

/// Reads a whole token as a number (all of it must be read); nothing otherwise.
std::optional<SpiceNumber> spice_number(std::string_view token);

} // namespace thermnet::importer::spice
