#include "lang/evaluator.hpp"
#include "lang/units.hpp"

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <span>
#include <vector>

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
  if (absolute_temperature && d == dim::temperature)
    return fmt::format("{:g} degC", si - kZeroCelsius);
  if (d.dimensionless()) return fmt::format("{:g}", si);
  return fmt::format("{:g} {}", si, describe(d));
}

std::string format_outside(double si, const KeySchema& key, const Dimension& d,
                           bool absolute_temperature) {
  const bool celsius = absolute_temperature && d == dim::temperature;
  const double shown = celsius ? si - kZeroCelsius : si;
  // The short form, read back: if the key accepts it, it hides the violation.
  const double read = std::strtod(fmt::format("{:g}", shown).c_str(), nullptr);
  if (!key.accepts(celsius ? read + kZeroCelsius : read))
    return format_value(si, d, absolute_temperature);
  const std::string digits = fmt::format("{}", shown); // the shortest text that reads back exactly
  if (celsius) return digits + " degC";
  if (d.dimensionless()) return digits;
  return fmt::format("{} {}", digits, describe(d));
}

void Evaluator::fail(Diagnostic d) const {
  throw EvalError(std::move(d));
}

Quantity Evaluator::eval(const ast::Expr& e) const {
  return checked(e.root);
}

Quantity Evaluator::checked(ast::Index i) const {
  Quantity q = node(i);
  if (!std::isfinite(q.value)) {
    const ast::ExprNode& n = file_.node(i);
    fail(DiagnosticEngine::make(DiagId::not_finite, span(n), span(n), "the expression",
                                fmt::format("{}", q.value)));
  }
  return q;
}

Quantity Evaluator::node(ast::Index i) const {
  using Op = ast::ExprNode::Op;
  const ast::ExprNode& n = file_.node(i);
  switch (n.op) {
  case Op::number:
    return Quantity{n.value, std::nullopt};
  case Op::quantity:
    return quantity(n);
  case Op::name: {
    const ast::Identifier& id = file_.names[n.a];
    if (id.name == "pi") return Quantity{std::numbers::pi, std::nullopt};
    if (id.name == "sigma") return Quantity{stefan_boltzmann, sigma_dim};
    return lookup_(id, file_.file_id);
  }
  case Op::call:
    return call(n);
  case Op::signal:
  case Op::ref:
    if (!signals_)
      fail(DiagnosticEngine::make(DiagId::signal_misplaced, span(n), span(n),
                                  n.op == Op::ref ? "a key of another element" : "a signal"));
    return signals_(i, file_.file_id);
  case Op::negate: {
    Quantity q = node(n.a);
    q.value = -q.value;
    q.zero = -q.zero;
    return q;
  }
  case Op::add:
  case Op::subtract:
    return sum(i);
  case Op::multiply:
  case Op::divide:
    return product(i);
  case Op::power:
    return power(i);
  case Op::group: {
    // A parenthesised expression is checked as a whole, marked with its parentheses.
    Quantity q = node(n.a);
    if (!std::isfinite(q.value))
      fail(DiagnosticEngine::make(DiagId::not_finite, span(n), span(n), "the expression",
                                  fmt::format("{}", q.value)));
    return q;
  }
  }
  return Quantity{};
}

Quantity Evaluator::sum(ast::Index i) const {
  using Op = ast::ExprNode::Op;
  std::vector<ast::Index> chain; // the operations from the right end, walked left
  while (file_.node(i).op == Op::add || file_.node(i).op == Op::subtract) {
    chain.push_back(i);
    i = file_.node(i).a;
  }
  Quantity acc = node(i);
  for (std::size_t k = chain.size(); k-- > 0;) {
    const ast::ExprNode& op = file_.node(chain[k]);
    acc = combine_sum(acc, node(op.b), op.op == Op::add, file_.node(op.b));
  }
  return acc;
}

Quantity Evaluator::combine_sum(Quantity a, Quantity b, bool add, const ast::Tagged& where) const {
  if (a.dim && b.dim && !(*a.dim == *b.dim))
    fail(DiagnosticEngine::make(DiagId::unit_mix, span(where), span(where),
                                add ? "add" : "subtract", describe(*a.dim), describe(*b.dim)));
  return Quantity{add ? a.value + b.value : a.value - b.value, a.dim ? a.dim : b.dim,
                  add ? a.zero + b.zero : a.zero - b.zero};
}

Quantity Evaluator::product(ast::Index i) const {
  using Op = ast::ExprNode::Op;
  std::vector<ast::Index> chain;
  while (file_.node(i).op == Op::multiply || file_.node(i).op == Op::divide) {
    chain.push_back(i);
    i = file_.node(i).a;
  }
  Quantity acc = node(i);
  for (std::size_t k = chain.size(); k-- > 0;) {
    const ast::ExprNode& op = file_.node(chain[k]);
    Quantity rhs = node(op.b);
    const bool divide = op.op == Op::divide;
    // A shifted temperature scaled by a number stays shifted by as much (2 * 20 [degC]).
    double zero = 0.0;
    if (rhs.zero == 0.0)
      zero = divide ? acc.zero / rhs.value : acc.zero * rhs.value;
    else if (acc.zero == 0.0 && !divide)
      zero = rhs.zero * acc.value;
    acc = Quantity{divide ? acc.value / rhs.value : acc.value * rhs.value,
                   multiply(acc.dim, rhs.dim, divide), zero};
  }
  return acc;
}

// `a ^ b ^ c` is a ^ (b ^ c); an exponent's own signs apply to it after its powers. Every power of
// a chain spans the whole chain, which messages mark.
Quantity Evaluator::power(ast::Index i) const {
  using Op = ast::ExprNode::Op;
  const ast::ExprNode& top = file_.node(i);
  struct Link {
    ast::Index operand;
    bool negated;
  };
  std::vector<Link> links; // the chain's inner bases, outermost first
  ast::Index last = top.b;
  for (;;) {
    const ast::ExprNode& e = file_.node(last);
    const bool negated = e.op == Op::negate && file_.node(e.a).op == Op::power;
    const ast::ExprNode& p = negated ? file_.node(e.a) : e;
    if (p.op != Op::power) break;
    links.push_back({p.a, negated});
    last = p.b;
  }
  Quantity exp = node(last);
  for (std::size_t k = links.size(); k-- > 0;) {
    exp = raise(node(links[k].operand), exp, top);
    if (links[k].negated) exp.value = -exp.value;
  }
  return raise(node(top.a), exp, top);
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

Quantity Evaluator::quantity(const ast::ExprNode& n) const {
  const ast::UnitText& unit = file_.units[n.a];
  try {
    Unit u = parse_unit(unit.text);
    return Quantity{u.scale * n.value + u.offset, u.dim, u.offset};
  } catch (const UnitError& e) {
    // The word at the error position (a unit symbol), to mark it whole and suggest a known one.
    std::string word;
    for (std::size_t i = e.offset; i < unit.text.size(); ++i) {
      char c = unit.text[i];
      if (!std::isalpha(static_cast<unsigned char>(c))) break;
      word += c;
    }
    auto at = static_cast<std::uint32_t>(unit.begin + e.offset); // begin: after the [
    auto len = static_cast<std::uint32_t>(std::max<std::size_t>(word.size(), 1));
    Span mark{file_.file_id, std::min(at, unit.end), std::min(at + len, unit.end)};
    Diagnostic d = DiagnosticEngine::make(DiagId::unknown_unit, span(n), mark, e.what());
    if (auto s = closest_match(word, known_unit_symbols()); s && *s != word)
      d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
    fail(std::move(d));
  }
}

Quantity Evaluator::call(const ast::ExprNode& c) const {
  const std::string_view f = file_.names[c.a].name;
  const std::span<const ast::Index> args = file_.call_args(c);
  auto arity = [&](std::size_t n) {
    if (args.size() != n)
      fail(DiagnosticEngine::make(DiagId::bad_function_arg, span(c), span(c),
                                  fmt::format("function '{}' takes {} argument{}, got {}", f, n,
                                              n == 1 ? "" : "s", args.size())));
  };
  auto dimensionless_arg = [&](std::size_t i) {
    Quantity q = checked(args[i]);
    if (!is_dimensionless(q.dim))
      fail(DiagnosticEngine::make(
          DiagId::bad_function_arg, span(file_.node(args[i])), span(file_.node(args[i])),
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
    Quantity q = checked(args[0]);
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
    Quantity q = checked(args[0]);
    return Quantity{std::abs(q.value), q.dim};
  }
  if (f == "min" || f == "max") {
    if (args.empty()) arity(1);
    Quantity acc = checked(args[0]);
    for (std::size_t i = 1; i < args.size(); ++i) {
      Quantity q = checked(args[i]);
      if (acc.dim && q.dim && !(*acc.dim == *q.dim))
        fail(DiagnosticEngine::make(DiagId::unit_mix, span(file_.node(args[i])),
                                    span(file_.node(args[i])), "compare", describe(*acc.dim),
                                    describe(*q.dim)));
      bool take = f == "min" ? q.value < acc.value : q.value > acc.value;
      acc = Quantity{take ? q.value : acc.value, acc.dim ? acc.dim : q.dim};
    }
    return acc;
  }
  if (f == "pow") {
    arity(2);
    return raise(checked(args[0]), checked(args[1]), c);
  }
  Diagnostic d =
      DiagnosticEngine::make(DiagId::unknown_function, span(c), span(file_.names[c.a]), f);
  static const std::vector<std::string> names = {"sqrt", "exp", "log", "log10", "sin", "cos",
                                                 "tan",  "abs", "min", "max",   "pow"};
  if (auto s = closest_match(std::string(f), names))
    d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
  fail(std::move(d));
}

} // namespace thermnet::lang
