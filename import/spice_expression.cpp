#include "import/spice_expression.hpp"

#include "import/fortran_number.hpp"
#include "import/report.hpp"
#include "import/spice_number.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <utility>
#include <vector>

namespace thermnet::importer::spice {

namespace {

/// How deep parentheses and unary signs may nest (a hostile expression cannot exhaust the stack).
constexpr int max_depth = 200;

// The name (letters, digits, '_') that starts at i, lower case as SPICE reads it; i moves past it.
std::string read_name(std::string_view s, std::size_t& i) {
  const std::size_t start = i;
  while (i < s.size() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '_'))
    ++i;
  std::string name(s.substr(start, i - start));
  std::transform(name.begin(), name.end(), name.begin(), [](char ch) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  });
  return name;
}

// A place in an expression's text: the text, where reading stands, spaces skipped, a character
// taken (shared by the evaluator and the translator).
struct Cursor {
  std::string_view s_;
  std::size_t i_ = 0;
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_])))
      ++i_;
  }
  bool eat(char c) {
    skip();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
};

class Parser : Cursor {
public:
  Parser(std::string_view text, lang::FileId file, std::uint32_t offset, const ParamLookup& lookup)
      : Cursor{text}, file_(file), offset_(offset), lookup_(lookup) {}

  double parse() {
    const double v = sum();
    skip();
    if (i_ < s_.size()) fail("unexpected '" + std::string(1, s_[i_]) + "'");
    if (!std::isfinite(v))
      throw ImportError(span(0, s_.size()), "bad-expression",
                        "the expression's value is not finite");
    return v;
  }

private:
  [[noreturn]] void fail(const std::string& message) const {
    throw ImportError(span(i_, i_ + 1), "bad-expression", message);
  }
  lang::Span span(std::size_t a, std::size_t b) const {
    const auto at = [&](std::size_t k) { return offset_ + static_cast<std::uint32_t>(k); };
    return lang::Span{file_, at(std::min(a, s_.size())),
                      at(std::max(std::min(b, s_.size()), a + 1))};
  }
  /// `result` of an operation on `operand`: a result that underflows to 0 from a nonzero
  /// operand is an error (a capacity or resistance gone without a word), as a literal's is.
  double checked(double operand, double result) const {
    if (result == 0 && operand != 0)
      throw ImportError(span(0, s_.size()), "bad-number",
                        "the expression's value underflows: its magnitude is below the smallest "
                        "number (4.9e-324)");
    return result;
  }
  void enter() {
    if (++depth_ > max_depth) fail("the expression nests too deeply");
  }

  double sum() {
    enter();
    double v = product();
    for (;;) {
      if (eat('+'))
        v += product();
      else if (eat('-'))
        v -= product();
      else
        break;
    }
    --depth_;
    return v;
  }
  double product() {
    double v = power();
    for (;;) {
      skip();
      if (i_ + 1 < s_.size() && s_[i_] == '*' && s_[i_ + 1] == '*') break; // a power
      if (eat('*'))
        v = checked(v, v * power());
      else if (eat('/')) {
        const std::size_t at = i_;
        const double d = power();
        if (d == 0) {
          i_ = at;
          fail("division by zero");
        }
        v = checked(v, v / d);
      } else
        break;
    }
    return v;
  }
  double power() {
    const double base = unary();
    skip();
    if (eat('^')) return checked(base, std::pow(base, power_rhs()));
    if (i_ + 1 < s_.size() && s_[i_] == '*' && s_[i_ + 1] == '*') {
      i_ += 2;
      return checked(base, std::pow(base, power_rhs()));
    }
    return base;
  }
  double power_rhs() {
    enter();
    const double v = power();
    --depth_;
    return v;
  }
  double unary() {
    enter();
    double v = 0;
    if (eat('-'))
      v = -unary();
    else if (eat('+'))
      v = unary();
    else
      v = primary();
    --depth_;
    return v;
  }
  double primary() {
    skip();
    if (i_ >= s_.size()) fail("the expression ends too early");
    if (eat('(')) {
      const double v = sum();
      if (!eat(')')) fail("expected ')'");
      return v;
    }
    const char c = s_[i_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      auto n = read_spice_number(s_.substr(i_));
      if (!n) fail("not a number");
      if (n->underflow)
        throw ImportError(span(i_, i_ + n->length), "bad-number",
                          underflow_message(s_.substr(i_, n->length)));
      i_ += n->length;
      return n->value;
    }
    if (!(std::isalpha(static_cast<unsigned char>(c)) || c == '_'))
      fail("unexpected '" + std::string(1, c) + "'");
    const std::size_t start = i_;
    const std::string name = read_name(s_, i_);
    skip();
    if (i_ < s_.size() && s_[i_] == '(') {
      ++i_;
      std::vector<double> args;
      if (!eat(')')) {
        do
          args.push_back(sum());
        while (eat(','));
        if (!eat(')')) fail("expected ')' or ','");
      }
      return call(name, args, start);
    }
    if (name == "pi") return 3.14159265358979323846;
    if (auto v = lookup_(name)) return *v;
    throw ImportError(span(start, start + name.size()), "unknown-param",
                      fmt::format("no parameter is called '{}'", lang::excerpt_for_display(name)));
  }
  double call(const std::string& f, const std::vector<double>& a, std::size_t at) {
    const auto need = [&](std::size_t n) {
      if (a.size() != n)
        throw ImportError(span(at, at + f.size()), "bad-expression",
                          fmt::format("{}() takes {} argument{}", f, n, n == 1 ? "" : "s"));
    };
    if (f == "min" || f == "max") {
      if (a.empty())
        throw ImportError(span(at, at + f.size()), "bad-expression", f + "() needs arguments");
      return f == "min" ? *std::min_element(a.begin(), a.end())
                        : *std::max_element(a.begin(), a.end());
    }
    if (f == "pow" || f == "pwr") {
      need(2);
      return std::pow(a[0], a[1]);
    }
    struct Fn {
      const char* name;
      double (*fn)(double);
    };
    static const Fn one[] = {{"sqrt", [](double x) { return std::sqrt(x); }},
                             {"exp", [](double x) { return std::exp(x); }},
                             {"ln", [](double x) { return std::log(x); }},
                             {"log", [](double x) { return std::log(x); }},
                             {"log10", [](double x) { return std::log10(x); }},
                             {"abs", [](double x) { return std::fabs(x); }},
                             {"sin", [](double x) { return std::sin(x); }},
                             {"cos", [](double x) { return std::cos(x); }},
                             {"tan", [](double x) { return std::tan(x); }},
                             {"atan", [](double x) { return std::atan(x); }},
                             {"sinh", [](double x) { return std::sinh(x); }},
                             {"cosh", [](double x) { return std::cosh(x); }},
                             {"tanh", [](double x) { return std::tanh(x); }},
                             {"floor", [](double x) { return std::floor(x); }},
                             {"ceil", [](double x) { return std::ceil(x); }},
                             {"int", [](double x) { return std::trunc(x); }}};
    for (const Fn& fn : one)
      if (f == fn.name) {
        need(1);
        const double v = f == "exp" ? checked(1, fn.fn(a[0])) : fn.fn(a[0]);
        if (!std::isfinite(v))
          throw ImportError(span(at, at + f.size()), "bad-expression",
                            fmt::format("{}({}) is not a finite number", f, a[0]));
        return v;
      }
    throw ImportError(span(at, at + f.size()), "bad-expression",
                      fmt::format("unknown function '{}'", lang::excerpt_for_display(f)));
  }

  lang::FileId file_;
  std::uint32_t offset_;
  const ParamLookup& lookup_;
  int depth_ = 0;
};

/// A thermnet expression's text and how tightly it binds: 0 a sum, 1 a product, 2 a negation,
/// 3 a power, 4 an atom (a number, a name, a call, a parenthesised expression).
struct Text {
  std::string s;
  int prec = 4;
};

/// Rewrites an expression that evaluate() accepted as thermnet text (same grammar, same
/// precedence as that parser: a leading minus binds tighter than ^ there, so it is bracketed).
class Translator : Cursor {
public:
  Translator(std::string_view text, const NameText& names) : Cursor{text}, names_(names) {}

  std::optional<std::string> run() {
    Text t = sum();
    skip();
    if (!ok_ || i_ < s_.size()) return std::nullopt;
    return t.s;
  }

private:
  static std::string wrap(const Text& t, int need) { return t.prec < need ? "(" + t.s + ")" : t.s; }
  Text fail() {
    ok_ = false;
    i_ = s_.size();
    return {"0", 4};
  }
  Text sum() {
    if (++depth_ > max_depth) return fail();
    Text v = product();
    for (;;) {
      char op = 0;
      if (eat('+'))
        op = '+';
      else if (eat('-'))
        op = '-';
      else
        break;
      const Text r = product();
      v = {wrap(v, 0) + " " + op + " " + wrap(r, 1), 0};
    }
    --depth_;
    return v;
  }
  Text product() {
    Text v = power();
    for (;;) {
      skip();
      if (i_ + 1 < s_.size() && s_[i_] == '*' && s_[i_ + 1] == '*') break;
      char op = 0;
      if (eat('*'))
        op = '*';
      else if (eat('/'))
        op = '/';
      else
        break;
      const Text r = power();
      v = {wrap(v, 1) + " " + op + " " + wrap(r, 2), 1};
    }
    return v;
  }
  Text power() {
    const Text base = unary();
    skip();
    bool pow = eat('^');
    if (!pow && i_ + 1 < s_.size() && s_[i_] == '*' && s_[i_ + 1] == '*') {
      i_ += 2;
      pow = true;
    }
    if (!pow) return base;
    if (++depth_ > max_depth) return fail();
    const Text e = power();
    --depth_;
    return {wrap(base, 4) + "^" + wrap(e, 3), 3};
  }
  Text unary() {
    if (++depth_ > max_depth) return fail();
    Text v;
    if (eat('-')) {
      const Text x = unary();
      v = {"-" + wrap(x, 3), 2};
    } else if (eat('+'))
      v = unary();
    else
      v = primary();
    --depth_;
    return v;
  }
  Text primary() {
    skip();
    if (i_ >= s_.size()) return fail();
    if (eat('(')) {
      const Text v = sum();
      if (!eat(')')) return fail();
      return {wrap(v, 4), 4};
    }
    const char c = s_[i_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      auto n = read_spice_number(s_.substr(i_));
      if (!n) return fail();
      i_ += n->length;
      return number(n->value);
    }
    if (!(std::isalpha(static_cast<unsigned char>(c)) || c == '_')) return fail();
    const std::string name = read_name(s_, i_);
    skip();
    if (i_ < s_.size() && s_[i_] == '(') {
      ++i_;
      std::vector<Text> args;
      if (!eat(')')) {
        do
          args.push_back(sum());
        while (eat(','));
        if (!eat(')')) return fail();
      }
      // Functions thermnet has with the same meaning (ngspice's log is natural, as thermnet's).
      static const std::pair<const char*, const char*> same[] = {
          {"sqrt", "sqrt"},   {"exp", "exp"}, {"ln", "log"},  {"log", "log"},
          {"log10", "log10"}, {"abs", "abs"}, {"sin", "sin"}, {"cos", "cos"},
          {"tan", "tan"},     {"min", "min"}, {"max", "max"}, {"pow", "pow"}};
      for (const auto& [spice, tnet] : same)
        if (name == spice) {
          std::string text = std::string(tnet) + "(";
          for (std::size_t k = 0; k < args.size(); ++k)
            text += (k ? ", " : "") + args[k].s;
          return {text + ")", 4};
        }
      return fail();
    }
    if (name == "pi") return {"pi", 4};
    auto t = names_(name);
    if (!t) return fail();
    return {*t, !t->empty() && (*t)[0] == '-' ? 2 : 4};
  }
  static Text number(double v) {
    std::string t = v == 0 ? "0" : fmt::format("{}", v);
    return {t, t[0] == '-' ? 2 : 4};
  }

  const NameText& names_;
  int depth_ = 0;
  bool ok_ = true;
};

} // namespace

std::optional<std::string> translate(std::string_view text, const NameText& name_text) {
  return Translator(text, name_text).run();
}

double evaluate(std::string_view text, lang::FileId file, std::uint32_t offset,
                const ParamLookup& lookup) {
  return Parser(text, file, offset, lookup).parse();
}

} // namespace thermnet::importer::spice
