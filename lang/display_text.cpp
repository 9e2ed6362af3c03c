// escape_for_display(): invalid UTF-8 as <A5>, control and bidi characters as <U+001B>.

#include "lang/display_text.hpp"

#include <fmt/format.h>

namespace thermnet::lang {

namespace {

/// Length of the valid UTF-8 sequence starting at s[i] (1-4) and its code point, or 0 when the
/// byte does not start one (overlong forms, surrogates and values past U+10FFFF are invalid).
std::size_t decode(std::string_view s, std::size_t i, char32_t& cp) {
  const auto b0 = static_cast<unsigned char>(s[i]);
  std::size_t n = 0;
  if (b0 < 0x80) {
    cp = b0;
    return 1;
  }
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    n = 2;
    cp = b0 & 0x1Fu;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    n = 3;
    cp = b0 & 0x0Fu;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    n = 4;
    cp = b0 & 0x07u;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    const auto b = static_cast<unsigned char>(s[i + k]);
    if ((b & 0xC0u) != 0x80u) return 0;
    cp = (cp << 6) | (b & 0x3Fu);
  }
  const char32_t min[] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < min[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return n;
}

/// Control characters and the bidirectional formatting characters that can reorder what a
/// reader sees (CVE-2021-42574).
bool hidden(char32_t cp) {
  return cp < 0x20 || (cp >= 0x7F && cp <= 0x9F) || (cp >= 0x202A && cp <= 0x202E) ||
         (cp >= 0x2066 && cp <= 0x2069) || cp == 0x200E || cp == 0x200F || cp == 0x061C;
}

} // namespace

std::string escape_for_display(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    char32_t cp = 0;
    const std::size_t n = decode(s, i, cp);
    if (n == 0) {
      out += fmt::format("<{:02X}>", static_cast<unsigned char>(s[i]));
      ++i;
    } else {
      if (hidden(cp))
        out += fmt::format("<U+{:04X}>", static_cast<std::uint32_t>(cp));
      else
        out.append(s.substr(i, n));
      i += n;
    }
  }
  return out;
}

std::string excerpt_for_display(std::string_view s, std::size_t max_chars) {
  std::size_t i = 0, chars = 0;
  while (i < s.size() && chars < max_chars) {
    char32_t cp = 0;
    const std::size_t n = decode(s, i, cp);
    i += n == 0 ? 1 : n;
    ++chars;
  }
  std::string out = escape_for_display(s.substr(0, i));
  if (i < s.size()) out += "...";
  return out;
}

} // namespace thermnet::lang
