#pragma once
/// Time-dependent values in SI: constant, piecewise constant (step), piecewise linear (pwl,
/// table), or an expression of the time.

#include <memory>
#include <vector>

namespace thermnet::lang {

class TimeProgram;

/// A value over time; times in s, values in SI (K for temperatures, W for powers).
struct Signal {
  /// The shape of a signal.
  enum class Kind { constant, step, pwl, expression };
  Kind kind = Kind::constant; ///< shape
  double constant = 0.0;      ///< value when kind == constant
  std::vector<double> t;      ///< corner times, increasing (step, pwl)
  std::vector<double> v;      ///< values at the corners (step: held until the next corner)
  /// The expression of the time (kind == expression): its value is program(t) * scale + offset.
  std::shared_ptr<const TimeProgram> program;
  double scale = 1.0;  ///< factor on the program's value (expression)
  double offset = 0.0; ///< added after the factor (expression; 273.15 for a bare degC value)

  /// A constant signal.
  static Signal of(double value) {
    Signal s;
    s.constant = value;
    return s;
  }
  /// The value at a time (step: v_k on [t_k, t_k+1), first value before t_0; pwl: clamped at the
  /// ends; expression: computed).
  double at(double time) const;
  /// True for a constant.
  bool is_constant() const { return kind == Kind::constant; }
  /// Times where the signal jumps or bends (where an integrator should restart).
  const std::vector<double>& corners() const { return t; }
  /// Multiplies every value by a factor.
  Signal scaled(double factor) const;
};

} // namespace thermnet::lang
