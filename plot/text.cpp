#include "plot/text.hpp"

#include <array>
#include <cstdint>

namespace thermnet::plot {
namespace {

// Length of the UTF-8 sequence starting at s[i], or 0 if it is not valid.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  if (c < 0x80) return 1;
  std::size_t len = 0;
  std::uint32_t cp = 0;
  if ((c & 0xE0) == 0xC0) {
    len = 2;
    cp = c & 0x1F;
  } else if ((c & 0xF0) == 0xE0) {
    len = 3;
    cp = c & 0x0F;
  } else if ((c & 0xF8) == 0xF0) {
    len = 4;
    cp = c & 0x07;
  } else {
    return 0;
  }
  if (i + len > s.size()) return 0;
  for (std::size_t k = 1; k < len; ++k) {
    const auto d = static_cast<unsigned char>(s[i + k]);
    if ((d & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (d & 0x3F);
  }
  // Reject overlong forms, surrogates, out-of-range values and the XML non-characters.
  if ((len == 2 && cp < 0x80) || (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000)) return 0;
  if ((cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF || cp == 0xFFFE || cp == 0xFFFF) return 0;
  return len;
}

// Advance widths (em) of printable ASCII in DejaVu Sans, the widest of the usual sans-serif
// fonts, so layout estimates err on the generous side.
constexpr std::array<double, 95> kAsciiWidth = {
    0.318, 0.400, 0.460, 0.838, 0.636, 0.950, 0.780, 0.275, 0.390, 0.390, 0.500, 0.838,
    0.318, 0.361, 0.318, 0.337, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636,
    0.636, 0.636, 0.337, 0.337, 0.838, 0.838, 0.838, 0.531, 1.000, 0.684, 0.686, 0.698,
    0.770, 0.632, 0.575, 0.775, 0.752, 0.295, 0.295, 0.656, 0.557, 0.863, 0.748, 0.787,
    0.603, 0.787, 0.695, 0.635, 0.611, 0.732, 0.684, 0.989, 0.685, 0.611, 0.685, 0.390,
    0.337, 0.390, 0.838, 0.500, 0.500, 0.613, 0.635, 0.550, 0.635, 0.615, 0.352, 0.635,
    0.634, 0.278, 0.278, 0.579, 0.278, 0.974, 0.634, 0.612, 0.635, 0.635, 0.411, 0.521,
    0.392, 0.634, 0.592, 0.818, 0.592, 0.592, 0.525, 0.636, 0.337, 0.636, 0.838};

// Estimated advance (em) of the code point starting at s[i] of valid UTF-8; sets len.
double char_em(std::string_view s, std::size_t i, std::size_t& len) {
  const auto c = static_cast<unsigned char>(s[i]);
  if (c < 0x80) {
    len = 1;
    return c >= 0x20 && c < 0x7F ? kAsciiWidth[c - 0x20] : 0.6;
  }
  len = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : 4;
  if (s.substr(i, len) == "\xE2\x80\xA6") return 1.0; // ellipsis
  return len >= 3 ? 0.9 : 0.7;                        // accented/Greek letters; symbols, CJK
}

} // namespace

std::string sanitize(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t len = utf8_length(s, i);
    if (len == 0) {
      out += "\xEF\xBF\xBD";
      ++i;
    } else if (len == 1) {
      const auto c = static_cast<unsigned char>(s[i]);
      out += (c < 0x20 || c == 0x7F) ? ' ' : s[i];
      ++i;
    } else {
      out.append(s.substr(i, len));
      i += len;
    }
  }
  return out;
}

double text_width(std::string_view s, double font_size) {
  double em = 0;
  for (std::size_t i = 0, len = 1; i < s.size(); i += len)
    em += char_em(s, i, len);
  return em * font_size;
}

std::string truncate(std::string_view s, double width, double font_size) {
  if (text_width(s, font_size) <= width) return std::string(s);
  const double room = width - 1.0 * font_size; // keep space for the ellipsis
  double used = 0;
  std::size_t i = 0;
  for (std::size_t len = 1; i < s.size(); i += len) {
    const double w = char_em(s, i, len) * font_size;
    if (used + w > room) break;
    used += w;
  }
  std::string out(s.substr(0, i));
  while (!out.empty() && out.back() == ' ')
    out.pop_back();
  return out + "\xE2\x80\xA6";
}

std::string fit_text(std::string_view raw, double width, double font_size, bool bold) {
  return truncate(sanitize(raw), bold ? width / 1.1 : width, font_size);
}

void append_escaped(std::string& out, std::string_view s) {
  for (const char c : s) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    case '\'':
      out += "&apos;";
      break;
    default:
      out += c;
    }
  }
}

std::string xml_escape(std::string_view text) {
  std::string out;
  append_escaped(out, sanitize(text));
  return out;
}

} // namespace thermnet::plot
