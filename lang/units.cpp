/// The units table and the unit-expression parser behind parse_unit() and describe().

#include "lang/units.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <utility>

namespace thermnet::lang {
namespace {

// Written exponents and the exponents of every intermediate result stay within this bound, so
// the int8 exponents of Dimension can never wrap and no real unit is rejected.
constexpr int kMaxExponent = 20;
// Recursion happens only on '('; bounding the depth bounds the stack for hostile input.
constexpr int kMaxDepth = 32;
// Symbols quoted in messages are cut here, so 1 MB of letters does not become a 1 MB message.
constexpr std::size_t kMaxQuoted = 40;

constexpr double kRankine = 5.0 / 9.0; // one degF (and one degR) in kelvin

/// One row of the units table.
struct Entry {
  std::string_view symbol;
  double scale;       // factor to SI; for temperature scales this is the size of one degree
  double lone_offset; // SI offset when the symbol is the whole unit (absolute temperatures)
  Dimension dim;
  bool prefixable; // accepts SI prefixes ("km", "mW"); false for min, h, degC, in, ...
};

constexpr Dimension kCurrent{{0, 0, 0, 0, 1, 0, 0}};
constexpr Dimension kAmount{{0, 0, 0, 0, 0, 1, 0}};
constexpr Dimension kLuminous{{0, 0, 0, 0, 0, 0, 1}};
constexpr Dimension kForce{{1, 1, -2, 0, 0, 0, 0}};
constexpr Dimension kPressure{{-1, 1, -2, 0, 0, 0, 0}};
constexpr Dimension kVoltage = dim::power / kCurrent;
constexpr Dimension kVolume = dim::area * dim::length;
constexpr Dimension kFrequency = dim::none / dim::time;

// "C" (coulomb) is deliberately absent: in a thermal model a bare "C" almost always means
// Celsius, and silently reading it as a charge would only surface as a confusing dimension error.
constexpr auto kTable = std::to_array<Entry>({
    {"m", 1.0, 0.0, dim::length, true},
    {"g", 1e-3, 0.0, dim::mass, true},
    {"s", 1.0, 0.0, dim::time, true},
    {"K", 1.0, 0.0, dim::temperature, true},
    {"A", 1.0, 0.0, kCurrent, true},
    {"mol", 1.0, 0.0, kAmount, true},
    {"cd", 1.0, 0.0, kLuminous, true},
    {"N", 1.0, 0.0, kForce, true},
    {"J", 1.0, 0.0, dim::energy, true},
    {"W", 1.0, 0.0, dim::power, true},
    {"Pa", 1.0, 0.0, kPressure, true},
    {"Hz", 1.0, 0.0, kFrequency, true},
    {"V", 1.0, 0.0, kVoltage, true},
    {"L", 1e-3, 0.0, kVolume, true},
    {"bar", 1e5, 0.0, kPressure, true},
    {"Wh", 3600.0, 0.0, dim::energy, true},
    {"cal", 4.184, 0.0, dim::energy, true}, // thermochemical calorie
    {"rad", 1.0, 0.0, dim::none, false},
    {"sr", 1.0, 0.0, dim::none, false},
    {"min", 60.0, 0.0, dim::time, false},
    {"h", 3600.0, 0.0, dim::time, false},
    {"day", 86400.0, 0.0, dim::time, false},
    {"degC", 1.0, kZeroCelsius, dim::temperature, false},
    // "\xC2\xB0" is the UTF-8 degree sign; the literal is split because "\xB0C" would be read
    // as a single hex escape.
    {"\xC2\xB0"
     "C",
     1.0, kZeroCelsius, dim::temperature, false},
    {"degF", kRankine, 459.67 * kRankine, dim::temperature, false},
    {"\xC2\xB0"
     "F",
     kRankine, 459.67 * kRankine, dim::temperature, false},
    {"degR", kRankine, 0.0, dim::temperature, false},
    {"in", 0.0254, 0.0, dim::length, false},
    {"ft", 0.3048, 0.0, dim::length, false},
    {"%", 0.01, 0.0, dim::none, false},
});

/// An SI prefix and its factor.
struct Prefix {
  std::string_view symbol;
  double scale;
};

// "da" precedes "d" only for readability: no table symbol starts with 'a', so the order never
// changes a result.
constexpr auto kPrefixes = std::to_array<Prefix>({
    {"Y", 1e24},        {"Z", 1e21}, {"E", 1e18},  {"P", 1e15},  {"T", 1e12},
    {"G", 1e9},         {"M", 1e6},  {"k", 1e3},   {"h", 1e2},   {"da", 1e1},
    {"d", 1e-1},        {"c", 1e-2}, {"m", 1e-3},  {"u", 1e-6},  {"\xC2\xB5", 1e-6},
    {"\xCE\xBC", 1e-6}, {"n", 1e-9}, {"p", 1e-12}, {"f", 1e-15}, {"a", 1e-18},
});

constexpr std::array<std::string_view, 7> kBaseNames{"m", "kg", "s", "K", "A", "mol", "cd"};

/// Dimensions with an engineering name, preferred over the generic base-unit form.
constexpr auto kNamedDimensions = std::to_array<std::pair<Dimension, std::string_view>>({
    {dim::none, "1"},
    {dim::length, "m"},
    {dim::area, "m^2"},
    {kVolume, "m^3"},
    {dim::time, "s"},
    {dim::temperature, "K"},
    {dim::mass, "kg"},
    {dim::energy, "J"},
    {dim::power, "W"},
    {dim::capacity, "J/K"},
    {dim::conductance, "W/K"},
    {dim::resistance, "K/W"},
    {dim::conductivity, "W/(m*K)"},
    {dim::heat_transfer_coeff, "W/(m^2*K)"},
    {dim::specific_heat, "J/(kg*K)"},
    {dim::density, "kg/m^3"},
    {dim::power / dim::area, "W/m^2"},
    {dim::area / dim::time, "m^2/s"},
    {kPressure, "Pa"},
    {kFrequency, "1/s"},
    {dim::none / dim::temperature, "1/K"},
});

const Entry* find_entry(std::string_view symbol) {
  for (const Entry& e : kTable)
    if (e.symbol == symbol) return &e;
  return nullptr;
}

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}
bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}
bool is_alpha(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

/// Quotes text for a message, cut to kMaxQuoted bytes without splitting a UTF-8 sequence.
std::string quoted(std::string_view text) {
  if (text.size() <= kMaxQuoted) return "'" + std::string(text) + "'";
  std::size_t cut = kMaxQuoted;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80)
    --cut;
  return "'" + std::string(text.substr(0, cut)) + "...'";
}

/// Names a byte for a message; non-printable bytes are shown in hex so messages stay valid text.
std::string describe_byte(char c) {
  const auto b = static_cast<unsigned char>(c);
  if (b >= 0x20 && b < 0x7F) return std::string("character '") + c + "'";
  static constexpr char kHex[] = "0123456789ABCDEF";
  return std::string("byte 0x") + kHex[b >> 4] + kHex[b & 0xF];
}

/// A partial result of the parser; exponents are kept as int and checked at every step.
struct Value {
  double scale = 1.0;
  std::array<int, 7> exp{};
  bool lone = false; // one symbol, no operator or exponent applied: it may keep its offset
  double lone_offset = 0.0;
};

/// Recursive-descent parser over the unit text; recursion depth is bounded by kMaxDepth.
///   expr   := term (('*' | '.' | '·' | '/') term)*        left-associative
///   term   := factor ('^' exponent)?
///   factor := '(' expr ')' | '1' | symbol digits?          "m2", "s-1" shorthand
class Parser {
public:
  explicit Parser(std::string_view text) : t_(text) {}

  Unit run() {
    skip_space();
    if (at_end()) throw UnitError("empty unit", 0);
    const Value v = expr();
    // expr() stops only at the end of the text or at a ')' that no '(' opened.
    if (!at_end()) throw UnitError("unmatched ')'", pos_);
    Unit u;
    u.scale = v.scale;
    u.offset = v.lone ? v.lone_offset : 0.0;
    for (std::size_t i = 0; i < v.exp.size(); ++i)
      u.dim.exp[i] = static_cast<std::int8_t>(v.exp[i]);
    return u;
  }

private:
  bool at_end() const { return pos_ >= t_.size(); }
  char peek() const { return t_[pos_]; }
  bool has(std::size_t at, std::string_view s) const { return t_.substr(at).starts_with(s); }
  void skip_space() {
    while (!at_end() && is_space(peek()))
      ++pos_;
  }

  /// Byte length of the product or quotient operator at pos_, 0 if there is none.
  std::size_t operator_length() const {
    if (at_end()) return 0;
    if (peek() == '*' || peek() == '.' || peek() == '/') return 1;
    if (has(pos_, "\xC2\xB7")) return 2; // middle dot
    return 0;
  }

  /// Byte length of a symbol character at `at`: a letter, the micro signs or the degree sign.
  std::size_t symbol_char_length(std::size_t at) const {
    if (at >= t_.size()) return 0;
    if (is_alpha(t_[at])) return 1;
    if (has(at, "\xC2\xB5") || has(at, "\xCE\xBC") || has(at, "\xC2\xB0")) return 2;
    return 0;
  }

  bool starts_factor() const {
    return peek() == '(' || peek() == '%' || is_digit(peek()) || symbol_char_length(pos_) > 0;
  }

  Value expr() {
    Value v = term();
    for (;;) {
      skip_space();
      if (at_end() || peek() == ')') return v;
      const std::size_t op_pos = pos_;
      const std::size_t len = operator_length();
      if (len == 0) {
        // A space between two units multiplies them, as the spec writes units: [W/(m K)].
        if (pos_ > 0 && is_space(t_[pos_ - 1]) && starts_factor()) {
          combine(v, term(), 1, op_pos);
          continue;
        }
        if (starts_factor()) throw UnitError("expected '*' or '/' between units", pos_);
        throw UnitError("unexpected " + describe_byte(peek()) + " in unit", pos_);
      }
      const bool divide = peek() == '/';
      pos_ += len;
      skip_space();
      if (at_end() || peek() == ')')
        throw UnitError("dangling '" + std::string(t_.substr(op_pos, len)) +
                            "': expected a unit after it",
                        op_pos);
      combine(v, term(), divide ? -1 : 1, op_pos);
    }
  }

  Value term() {
    bool has_exponent = false;
    Value v = factor(has_exponent);
    skip_space();
    if (!at_end() && peek() == '^') {
      if (has_exponent) throw UnitError("a unit cannot take a second exponent", pos_);
      const std::size_t caret = pos_;
      power(v, exponent(), caret);
      skip_space();
      if (!at_end() && peek() == '^') throw UnitError("a unit cannot take a second exponent", pos_);
    }
    return v;
  }

  Value factor(bool& has_exponent) {
    const char c = peek();
    if (c == '(') return group();
    if (is_digit(c)) return number();
    if (c == '%' || symbol_char_length(pos_) > 0) return symbol(has_exponent);
    if (c == ')')
      throw UnitError(depth_ == 0 ? "unmatched ')'" : "expected a unit before ')'", pos_);
    if (const std::size_t len = operator_length(); len > 0)
      throw UnitError("expected a unit before '" + std::string(t_.substr(pos_, len)) + "'", pos_);
    throw UnitError("unexpected " + describe_byte(c) + " in unit", pos_);
  }

  Value group() {
    const std::size_t open = pos_;
    if (depth_ >= kMaxDepth)
      throw UnitError("parentheses nested deeper than " + std::to_string(kMaxDepth) + " levels",
                      open);
    ++pos_;
    ++depth_;
    skip_space();
    if (at_end()) throw UnitError("unclosed '('", open);
    if (peek() == ')') throw UnitError("empty parentheses", pos_);
    Value v = expr();
    if (at_end()) throw UnitError("unclosed '('", open);
    ++pos_; // expr() stopped at the matching ')'
    --depth_;
    return v; // "(degC)" is still a lone unit
  }

  /// A number is allowed only as the dimensionless "1" of "1/s"; anything else is a mistake
  /// (a value written inside the brackets), reported as a whole, decimals included.
  Value number() {
    const std::size_t start = pos_;
    while (!at_end() && is_digit(peek()))
      ++pos_;
    if (!at_end() && peek() == '.' && pos_ + 1 < t_.size() && is_digit(t_[pos_ + 1])) {
      ++pos_;
      while (!at_end() && is_digit(peek()))
        ++pos_;
    }
    const std::string_view text = t_.substr(start, pos_ - start);
    if (text != "1")
      throw UnitError("number " + quoted(text) + " is not a unit (only '1' is, as in '1/s')",
                      start);
    return Value{};
  }

  Value symbol(bool& has_exponent) {
    const std::size_t start = pos_;
    if (peek() == '%') {
      ++pos_;
    } else {
      while (const std::size_t n = symbol_char_length(pos_))
        pos_ += n;
    }
    Value v = resolve(t_.substr(start, pos_ - start), start);
    // Engineering shorthand: trailing digits are an exponent ("m2" is m^2, "s-1" is s^-1).
    if (!at_end() &&
        (is_digit(peek()) || (peek() == '-' && pos_ + 1 < t_.size() && is_digit(t_[pos_ + 1])))) {
      power(v, integer(), start);
      has_exponent = true;
    }
    return v;
  }

  /// Looks a symbol up: an exact table symbol wins over any prefix reading ("min", "cd", "Pa").
  Value resolve(std::string_view sym, std::size_t start) const {
    if (const Entry* e = find_entry(sym)) return atom(*e, 1.0);
    const Entry* unprefixable = nullptr;
    for (const Prefix& p : kPrefixes) {
      if (sym.size() <= p.symbol.size() || !sym.starts_with(p.symbol)) continue;
      if (const Entry* e = find_entry(sym.substr(p.symbol.size()))) {
        if (e->prefixable) return atom(*e, p.scale);
        unprefixable = e;
      }
    }
    if (unprefixable)
      throw UnitError("unit " + quoted(sym) + ": '" + std::string(unprefixable->symbol) +
                          "' takes no SI prefix",
                      start);
    std::string hint;
    if (sym == "C") hint = " (write 'degC' for degrees Celsius)";
    if (sym == "F") hint = " (write 'degF' for degrees Fahrenheit)";
    throw UnitError("unknown unit " + quoted(sym) + hint, start);
  }

  static Value atom(const Entry& e, double prefix) {
    Value v;
    v.scale = prefix * e.scale;
    for (std::size_t i = 0; i < v.exp.size(); ++i)
      v.exp[i] = e.dim.exp[i];
    v.lone = true;
    v.lone_offset = e.lone_offset; // only unprefixable temperatures have one
    return v;
  }

  /// Parses "^2", "^-1", "^(-1)" starting at the '^'.
  int exponent() {
    const std::size_t caret = pos_;
    ++pos_;
    skip_space();
    const std::size_t open = pos_;
    const bool paren = !at_end() && peek() == '(';
    if (paren) {
      ++pos_;
      skip_space();
    }
    std::size_t digits = pos_;
    if (digits < t_.size() && (t_[digits] == '+' || t_[digits] == '-')) ++digits;
    if (digits >= t_.size() || !is_digit(t_[digits]))
      throw UnitError("expected an integer exponent after '^'", at_end() ? caret : pos_);
    const int n = integer();
    if (paren) {
      skip_space();
      if (at_end()) throw UnitError("unclosed '(' in exponent", open);
      if (peek() != ')') throw UnitError("expected ')' to close the exponent", pos_);
      ++pos_;
    }
    return n;
  }

  /// Parses an optionally signed integer at pos_ (a digit is known to follow the sign).
  int integer() {
    const std::size_t start = pos_;
    int sign = 1;
    if (peek() == '+' || peek() == '-') {
      sign = peek() == '-' ? -1 : 1;
      ++pos_;
    }
    int value = 0;
    bool overflow = false;
    while (!at_end() && is_digit(peek())) {
      // Stop accumulating once out of range so a million digits cannot overflow the int.
      if (!overflow) value = value * 10 + (peek() - '0');
      overflow = overflow || value > kMaxExponent;
      ++pos_;
    }
    if (!at_end() && peek() == '.' && pos_ + 1 < t_.size() && is_digit(t_[pos_ + 1]))
      throw UnitError("fractional exponents are not supported", pos_);
    if (overflow)
      throw UnitError("exponent " + quoted(t_.substr(start, pos_ - start)) +
                          " out of range (at most " + std::to_string(kMaxExponent) +
                          " in magnitude)",
                      start);
    return sign * value;
  }

  /// a := a * b (sign 1) or a / b (sign -1), reported at `at` when out of range.
  static void combine(Value& a, const Value& b, int sign, std::size_t at) {
    for (std::size_t i = 0; i < a.exp.size(); ++i)
      a.exp[i] += sign * b.exp[i];
    a.scale = sign > 0 ? a.scale * b.scale : a.scale / b.scale;
    a.lone = false;
    check(a, at);
  }

  /// v := v ^ n, reported at `at` when out of range.
  static void power(Value& v, int n, std::size_t at) {
    for (int& e : v.exp)
      e *= n;
    v.scale = std::pow(v.scale, n);
    v.lone = false;
    check(v, at);
  }

  static void check(const Value& v, std::size_t at) {
    for (std::size_t i = 0; i < v.exp.size(); ++i)
      if (std::abs(v.exp[i]) > kMaxExponent)
        throw UnitError("exponent of '" + std::string(kBaseNames[i]) + "' out of range (at most " +
                            std::to_string(kMaxExponent) + " in magnitude)",
                        at);
    // Y^20 or a^20 would overflow or underflow a double; no real unit gets near.
    if (!std::isnormal(v.scale)) throw UnitError("unit scale out of range", at);
  }

  std::string_view t_;
  std::size_t pos_ = 0;
  int depth_ = 0;
};

} // namespace

Unit parse_unit(std::string_view text) {
  return Parser(text).run();
}

std::string describe(const Dimension& d) {
  for (const auto& [named, name] : kNamedDimensions)
    if (named == d) return std::string(name);
  // Generic form: mass first, as engineers write "kg*m^2/s^3", then the SI order.
  static constexpr std::array<std::size_t, 7> kOrder{1, 0, 2, 3, 4, 5, 6};
  std::string num;
  std::string den;
  int den_factors = 0;
  for (const std::size_t i : kOrder) {
    const int e = d.exp[i];
    if (e == 0) continue;
    std::string& out = e > 0 ? num : den;
    if (!out.empty()) out += '*';
    out += kBaseNames[i];
    if (std::abs(e) != 1) out += fmt::format("^{}", std::abs(e));
    if (e < 0) ++den_factors;
  }
  if (num.empty()) num.push_back('1'); // dimensionless numerator, as in 1/s
  if (den.empty()) return num;
  return den_factors > 1 ? fmt::format("{}/({})", num, den) : fmt::format("{}/{}", num, den);
}

const std::vector<std::string>& known_unit_symbols() {
  static const std::vector<std::string> symbols = [] {
    std::vector<std::string> out;
    out.reserve(kTable.size());
    for (const Entry& e : kTable)
      out.emplace_back(e.symbol);
    return out;
  }();
  return symbols;
}

} // namespace thermnet::lang
