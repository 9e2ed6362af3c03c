#pragma once
/// Evaluation of expressions to SI values with dimension analysis.

#include "lang/ast.hpp"
#include "lang/diagnostics.hpp"
#include "lang/schema.hpp"
#include "lang/units.hpp"

#include <exception>
#include <functional>
#include <optional>
#include <string>

namespace thermnet::lang {

/// A value in SI with its dimension; a bare number (no unit anywhere) has no dimension.
struct Quantity {
  double value = 0.0;           ///< SI value
  std::optional<Dimension> dim; ///< dimension, or none for a bare number
  /// What lone degC/degF units added to the value (273.15 for `20 [degC]`, 0 for `30 [degC] - 20
  /// [degC]`): value - zero is the value as a temperature difference.
  double zero = 0.0;
};

/// What a quantity adds where an absolute temperature is expected: kZeroCelsius for a bare number
/// (bare temperatures are degC), 0 for a value with a unit (already in K) and anywhere else.
inline double bare_temperature_offset(const Quantity& q, bool absolute_temperature) {
  return !q.dim && absolute_temperature ? kZeroCelsius : 0.0;
}

/// A problem found while evaluating: a complete diagnostic ready to report.
struct EvalError : std::exception {
  /// Wraps a diagnostic.
  explicit EvalError(Diagnostic d) : diag(std::move(d)) {}
  Diagnostic diag; ///< what went wrong, where
  /// The message.
  const char* what() const noexcept override { return diag.message.c_str(); }
};

/// Evaluates expressions of one file; names are resolved by a callback that may throw EvalError.
///
/// Chains of `+ -`, of `* /` and of `^` are walked in a loop, so the evaluation recurses only as
/// deep as parentheses and calls nest (which the parser bounds).
class Evaluator {
public:
  /// Resolves a const/param name to its value.
  using Lookup = std::function<Quantity(const ast::Identifier&, FileId)>;
  /// Resolves a signal or a key reference standing in an expression (ExprNode::signal, ::ref, by
  /// node index) to its value at t = 0 with its dimension; may throw EvalError.
  using SignalLookup = std::function<Quantity(ast::Index node, FileId)>;
  /// An evaluator for expressions written in `file`; without `signals`, a signal or a key
  /// reference in an expression is an error.
  Evaluator(const ast::File& file, Lookup lookup, SignalLookup signals = nullptr)
      : file_(file), lookup_(std::move(lookup)), signals_(std::move(signals)) {}
  /// Evaluates an expression; throws EvalError on unknown names, unit errors or non-finite results.
  Quantity eval(const ast::Expr& e) const;
  /// The span of a tagged node of this file.
  Span span(const ast::Tagged& t) const { return Span{file_.file_id, t.begin, t.end}; }

private:
  Quantity checked(ast::Index i) const;
  Quantity node(ast::Index i) const;
  Quantity sum(ast::Index i) const;
  Quantity product(ast::Index i) const;
  Quantity power(ast::Index i) const;
  Quantity quantity(const ast::ExprNode& n) const;
  Quantity call(const ast::ExprNode& c) const;
  Quantity combine_sum(Quantity a, Quantity b, bool add, const ast::Tagged& where) const;
  Quantity raise(Quantity base, Quantity exp, const ast::Tagged& where) const;
  [[noreturn]] void fail(Diagnostic d) const;

  const ast::File& file_;
  Lookup lookup_;
  SignalLookup signals_;
};

/// Formats an SI value with its unit for messages ("-5 W/K", "17 degC" for absolute temperatures).
std::string format_value(double si, const Dimension& dim, bool absolute_temperature = false);
/// format_value() of a value that `key` does not accept, with the digits it takes to show that
/// (1.0000000000000002 rather than 1 for a key in [0, 1]).
std::string format_outside(double si, const KeySchema& key, const Dimension& dim,
                           bool absolute_temperature = false);

} // namespace thermnet::lang
