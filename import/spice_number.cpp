#include "import/spice_number.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <string>

namespace thermnet::importer::spice {

namespace {

bool digit(char c) {
  return c >= '0' && c <= '9';
}

bool letter(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

char lower(char c) {
  return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
}

} // namespace

std::optional<SpiceNumber> read_spice_number(std::string_view text) {
  std::size_t i = 0;
  const std::size_t n = text.size();
  std::string normal;
  if (i < n && (text[i] == '+' || text[i] == '-')) {
    if (text[i] == '-') normal += '-';
    ++i;
  }
  std::size_t digits = 0;
  while (i < n && digit(text[i])) {
    normal += text[i++];
    ++digits;
  }
  if (i < n && text[i] == '.') {
    normal += text[i++];
    while (i < n && digit(text[i])) {
      normal += text[i++];
      ++digits;
    }
  }
  if (digits == 0) return std::nullopt;
  // An exponent: e or E, an optional sign, digits (else the e is a unit letter).
  if (i < n && (text[i] == 'e' || text[i] == 'E')) {
    std::size_t j = i + 1;
    if (j < n && (text[j] == '+' || text[j] == '-')) ++j;
    if (j < n && digit(text[j])) {
      normal += 'e';
      normal.append(text.substr(i + 1, j - i - 1));
      while (j < n && digit(text[j]))
        normal += text[j++];
      i = j;
    }
  }
  double value = 0;
  bool underflow = false;
  auto [p, ec] = std::from_chars(normal.data(), normal.data() + normal.size(), value);
  if (ec == std::errc::result_out_of_range && normal.find("e-") != std::string::npos) {
    value = 0;
    underflow = true;
  } else if (ec != std::errc() || p != normal.data() + normal.size() || !std::isfinite(value))
    return std::nullopt;
  SpiceNumber out;
  // The scale suffix.
  const auto starts = [&](std::string_view s) {
    if (n - i < s.size()) return false;
    for (std::size_t k = 0; k < s.size(); ++k)
      if (lower(text[i + k]) != s[k]) return false;
    return true;
  };
  double scale = 1;
  if (starts("meg")) {
    scale = 1e6;
    i += 3;
  } else if (starts("mil")) {
    scale = 25.4e-6;
    i += 3;
  } else if (i < n && letter(text[i])) {
    switch (lower(text[i])) {
    case 'f':
      scale = 1e-15;
      break;
    case 'p':
      scale = 1e-12;
      break;
    case 'n':
      scale = 1e-9;
      break;
    case 'u':
      scale = 1e-6;
      break;
    case 'm':
      scale = 1e-3;
      break;
    case 'k':
      scale = 1e3;
      break;
    case 'g':
      scale = 1e9;
      break;
    case 't':
      scale = 1e12;
      break;
    default:
      break;
    }
    if (scale != 1) {
      out.femto_alone = scale == 1e-15 && (i + 1 == n || !letter(text[i + 1]));
      ++i;
    }
  }
  while (i < n && letter(text[i])) // unit letters, ignored
    ++i;
  out.value = value * scale;
  if (!std::isfinite(out.value)) return std::nullopt;
  out.underflow = underflow || (value != 0 && out.value == 0);
  out.length = i;
  return out;
}

std::optional<SpiceNumber> spice_number(std::string_view token) {
  auto r = read_spice_number(token);
  if (!r || r->length != token.size()) return std::nullopt;
  return r;
}

} // namespace thermnet::importer::spice
