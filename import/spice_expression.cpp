#include "import/spice_expression.hpp"

#include "import/report.hpp"
#include "import/spice_number.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <vector>

namespace thermnet::importer::spice {

namespace {

/// How deep parentheses and unary signs may nest (a hostile expression cannot exhaust the stack).
constexpr int max_depth = 200;

class Parser {
public:
  Parser(std::string_view text, lang::FileId file, std::uint32_t offset, const ParamLookup& lookup)
      : s_(text), file_(file), offset_(offset), lookup_(lookup) {}

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
        v *= power();
      else if (eat('/')) {
        const std::size_t at = i_;
        const double d = power();
        if (d == 0) {
          i_ = at;
          fail("division by zero");
        }
        v /= d;
      } else
        break;
    }
    return v;
  }
  double power() {
    const double base = unary();
    skip();
    if (eat('^')) return std::pow(base, power_rhs());
    if (i_ + 1 < s_.size() && s_[i_] == '*' && s_[i_ + 1] == '*') {
      i_ += 2;
      return std::pow(base, power_rhs());
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
      i_ += n->length;
      return n->value;
    }
    if (!(std::isalpha(static_cast<unsigned char>(c)) || c == '_'))
      fail("unexpected '" + std::string(1, c) + "'");
    const std::size_t start = i_;
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_'))
      ++i_;
    std::string name(s_.substr(start, i_ - start));
    std::transform(name.begin(), name.end(), name.begin(), [](char ch) {
      return static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    });
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
        const double v = fn.fn(a[0]);
        if (!std::isfinite(v))
          throw ImportError(span(at, at + f.size()), "bad-expression",
                            fmt::format("{}({}) is not a finite number", f, a[0]));
        return v;
      }
    throw ImportError(span(at, at + f.size()), "bad-expression",
                      fmt::format("unknown function '{}'", lang::excerpt_for_display(f)));
  }

  std::string_view s_;
  lang::FileId file_;
  std::uint32_t offset_;
  const ParamLookup& lookup_;
  std::size_t i_ = 0;
  int depth_ = 0;
};

} // namespace

double evaluate(std::string_view text, lang::FileId file, std::uint32_t offset,
                const ParamLookup& lookup) {
  return Parser(text, file, offset, lookup).parse();
}

} // namespace thermnet::importer::spice
