#include "lang/evaluator.hpp"

#include <cmath>
#include <numbers>

namespace thermnet::lang {
namespace {

constexpr double stefan_boltzmann = 5.670374419e-8;
const Dimension sigma_dim = dim::power / dim::area / dim::temperature.pow(4);

std::string dim_text(const std::optional<Dimension>& d) {
  return d ? describe(*d) : std::string("1 (bare number)");
}

/// Dimension of a product/quotient: bare numbers act as dimensionless.
std::optional<Dimension> multiply(const std::optional<Dimension>& a,
                                  const std::optional<Dimension>& b, bool divide) {
  if (!a && !b) return std::nullopt;
  Dimension x = a.value_or(Dimension{}), y = b.value_or(Dimension{});
  return divide ? x / y : x * y;
}

bool is_dimensionless(const std::optional<Dimension>& d) {
  return !d || d->dimensionless();
}

} // namespace

std::string format_value(double si, const Dimension& d, bool absolute_temperature) {
  if (absolute_temperature && d == dim::temperature) return fmt::format("{:g} degC", si - 273.15);
  if (d.dimensionless()) return fmt::format("{:g}", si);
  return fmt::format("{:g} {}", si, describe(d));
}

void Evaluator::fail(Diagnostic d) const {
  throw EvalError(std::move(d));
}

Quantity Evaluator::eval(const ast::Expr& e) const {
  Quantity acc = term(e.first);
  for (const auto& op : e.rest)
    acc = combine_sum(acc, term(op.operand), op.op, op.operand);
  if (!std::isfinite(acc.value))
    fail(DiagnosticEngine::make(DiagId::not_finite, span(e), span(e), "the expression",
                                fmt::format("{}", acc.value)));
  return acc;
}

Quantity Evaluator::combine_sum(Quantity a, Quantity b, char op, const ast::Tagged& where) const {
  if (a.dim && b.dim && !(*a.dim == *b.dim))
    fail(DiagnosticEngine::make(DiagId::unit_mix, span(where), span(where),
                                op == '+' ? "add" : "subtract", describe(*a.dim),
                                describe(*b.dim)));
  return Quantity{op == '+' ? a.value + b.value : a.value - b.value, a.dim ? a.dim : b.dim};
}

Quantity Evaluator::term(const ast::Term& t) const {
  Quantity acc = signed_power(t.first);
  for (const auto& op : t.rest) {
    Quantity rhs = signed_power(op.operand);
    bool divide = op.op == '/';
    acc = Quantity{divide ? acc.value / rhs.value : acc.value * rhs.value,
                   multiply(acc.dim, rhs.dim, divide)};
  }
  return acc;
}

Quantity Evaluator::signed_power(const ast::Signed& s) const {
  // A signed number with a unit is one quantity: -10 [degC] is 263.15 K, not -(283.15 K).
  if (s.power.tail.empty())
    if (const auto* lit = boost::get<ast::Quantity>(&s.power.base); lit && lit->unit) {
      ast::Quantity signed_lit = *lit;
      for (char c : s.signs)
        if (c == '-') signed_lit.value = -signed_lit.value;
      return quantity(signed_lit);
    }
  Quantity q = power(s.power);
  for (char c : s.signs)
    if (c == '-') q.value = -q.value;
  return q;
}

Quantity Evaluator::power(const ast::Power& p) const {
  if (p.tail.empty()) return primary(p.base);
  // Right-associative: a ^ b ^ c = a ^ (b ^ c); evaluate the tail from the right.
  Quantity exp = primary(p.tail.back().operand);
  for (char c : p.tail.back().signs)
    if (c == '-') exp.value = -exp.value;
  for (std::size_t i = p.tail.size() - 1; i-- > 0;) {
    Quantity base = primary(p.tail[i].operand);
    exp = raise(base, exp, p);
    for (char c : p.tail[i].signs)
      if (c == '-') exp.value = -exp.value;
  }
  return raise(primary(p.base), exp, p);
}

Quantity Evaluator::raise(Quantity base, Quantity exp, const ast::Tagged& where) const {
  if (!is_dimensionless(exp.dim))
    fail(DiagnosticEngine::make(
        DiagId::bad_function_arg, span(where), span(where),
        fmt::format("an exponent must be dimensionless, not {}", describe(*exp.dim))));
  std::optional<Dimension> d;
  if (base.dim && !base.dim->dimensionless()) {
    double n = std::round(exp.value);
    if (n != exp.value || std::abs(n) > 20)
      fail(DiagnosticEngine::make(
          DiagId::bad_function_arg, span(where), span(where),
          fmt::format("a quantity of dimension {} can only be raised to a whole power, not {:g}",
                      describe(*base.dim), exp.value)));
    d = base.dim->pow(static_cast<int>(n));
  } else if (base.dim) {
    d = base.dim;
  }
  return Quantity{std::pow(base.value, exp.value), d};
}

Quantity Evaluator::primary(const ast::Primary& p) const {
  struct Visitor {
    const Evaluator& ev;
    Quantity operator()(const ast::Quantity& q) const { return ev.quantity(q); }
    Quantity operator()(const ast::Call& c) const { return ev.call(c); }
    Quantity operator()(const ast::Identifier& id) const {
      if (id.name == "pi") return Quantity{std::numbers::pi, std::nullopt};
      if (id.name == "sigma") return Quantity{stefan_boltzmann, sigma_dim};
      return ev.lookup_(id, ev.file_);
    }
    Quantity operator()(const ast::Expr& e) const { return ev.eval(e); }
  };
  return boost::apply_visitor(Visitor{*this}, p);
}

Quantity Evaluator::quantity(const ast::Quantity& q) const {
  if (!q.unit) return Quantity{q.value, std::nullopt};
  try {
    Unit u = parse_unit(q.unit->text);
    return Quantity{u.scale * q.value + u.offset, u.dim};
  } catch (const UnitError& e) {
    // The word at the error position (a unit symbol), to mark it whole and suggest a known one.
    std::string word;
    for (std::size_t i = e.offset; i < q.unit->text.size(); ++i) {
      char c = q.unit->text[i];
      if (!std::isalpha(static_cast<unsigned char>(c))) break;
      word += c;
    }
    auto at = static_cast<std::uint32_t>(q.unit->begin + e.offset); // begin: after the [
    auto len = static_cast<std::uint32_t>(std::max<std::size_t>(word.size(), 1));
    Span mark{file_, std::min(at, q.unit->end), std::min(at + len, q.unit->end)};
    Diagnostic d = DiagnosticEngine::make(DiagId::unknown_unit, span(q), mark, e.what());
    if (auto s = closest_match(word, known_unit_symbols()); s && *s != word)
      d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
    fail(std::move(d));
  }
}

Quantity Evaluator::call(const ast::Call& c) const {
  const std::string& f = c.function.name;
  auto arity = [&](std::size_t n) {
    if (c.args.size() != n)
      fail(DiagnosticEngine::make(DiagId::bad_function_arg, span(c), span(c),
                                  fmt::format("function '{}' takes {} argument{}, got {}", f, n,
                                              n == 1 ? "" : "s", c.args.size())));
  };
  auto dimensionless_arg = [&](std::size_t i) {
    Quantity q = eval(c.args[i]);
    if (!is_dimensionless(q.dim))
      fail(DiagnosticEngine::make(
          DiagId::bad_function_arg, span(c.args[i]), span(c.args[i]),
          fmt::format("the argument of '{}' must be dimensionless, not {}", f, dim_text(q.dim))));
    return q.value;
  };
  using Fn = double (*)(double);
  static const std::pair<const char*, Fn> unary[] = {{"exp", [](double x) { return std::exp(x); }},
                                                     {"log", [](double x) { return std::log(x); }},
                                                     {"log10", [](double x) { return std::log10(x); }},
                                                     {"sin", [](double x) { return std::sin(x); }},
                                                     {"cos", [](double x) { return std::cos(x); }},
                                                     {"tan", [](double x) { return std::tan(x); }}};
  for (const auto& [name, fn] : unary)
    if (f == name) {
      arity(1);
      return Quantity{fn(dimensionless_arg(0)), std::nullopt};
    }
  if (f == "sqrt") {
    arity(1);
    Quantity q = eval(c.args[0]);
    std::optional<Dimension> d;
    if (q.dim) {
      for (auto e : q.dim->exp)
        if (e % 2 != 0)
          fail(DiagnosticEngine::make(DiagId::bad_function_arg, span(c), span(c),
                                      fmt::format("the square root of a quantity of dimension {} "
                                                  "has no dimension",
                                                  describe(*q.dim))));
      Dimension h;
      for (std::size_t i = 0; i < h.exp.size(); ++i)
        h.exp[i] = static_cast<std::int8_t>(q.dim->exp[i] / 2);
      d = h;
    }
    return Quantity{std::sqrt(q.value), d};
  }
  if (f == "abs") {
    arity(1);
    Quantity q = eval(c.args[0]);
    return Quantity{std::abs(q.value), q.dim};
  }
  if (f == "min" || f == "max") {
    if (c.args.empty()) arity(1);
    Quantity acc = eval(c.args[0]);
    for (std::size_t i = 1; i < c.args.size(); ++i) {
      Quantity q = eval(c.args[i]);
      if (acc.dim && q.dim && !(*acc.dim == *q.dim))
        fail(DiagnosticEngine::make(DiagId::unit_mix, span(c.args[i]), span(c.args[i]), "compare",
                                    describe(*acc.dim), describe(*q.dim)));
      bool take = f == "min" ? q.value < acc.value : q.value > acc.value;
      acc = Quantity{take ? q.value : acc.value, acc.dim ? acc.dim : q.dim};
    }
    return acc;
  }
  if (f == "pow") {
    arity(2);
    return raise(eval(c.args[0]), eval(c.args[1]), c);
  }
  Diagnostic d = DiagnosticEngine::make(DiagId::unknown_function, span(c), span(c.function), f);
  static const std::vector<std::string> names = {"sqrt", "exp", "log", "log10", "sin", "cos",
                                                 "tan",  "abs", "min", "max",   "pow"};
  if (auto s = closest_match(f, names))
    d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
  fail(std::move(d));
}

} // namespace thermnet::lang
