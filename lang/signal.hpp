#pragma once
/// Time-dependent values in SI: constant, piecewise constant (step), piecewise linear (pwl,
/// table), or an expression of the time.

#include "lang/source.hpp"

#include <boost/smart_ptr/intrusive_ptr.hpp>
#include <boost/smart_ptr/intrusive_ref_counter.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace thermnet::lang {

class TimeProgram;

/// A value over time; times in s, values in SI (K for temperatures, W for powers).
///
/// Nearly every value of a netlist is a constant, so a signal is a number, a pointer and a hint
/// (24 bytes); the kind, corners and expression of the other kinds are kept on the heap, shared by
/// the signal's copies (a table of a million rows read by several elements and the model of every
/// simulation is held once) until one of them is changed through shape(), which makes its own.
struct Signal {
  /// The shape of a signal.
  enum class Kind : std::uint8_t { constant, step, pwl, expression };
  /// What a signal other than a constant holds (counted by the signals that share it).
  struct Shape : boost::intrusive_ref_counter<Shape, boost::thread_safe_counter> {
    Kind kind = Kind::constant; ///< shape of the signal
    /// Corner times, increasing (step, pwl); for an expression, the corners of the signals it
    /// reads (where it may jump or bend).
    std::vector<double> t;
    std::vector<double> v; ///< values at the corners (step: held until the next corner)
    /// The expression of the time (kind == expression): its value is program(t) * scale + offset.
    std::shared_ptr<const TimeProgram> program;
    double scale = 1.0;  ///< factor on the program's value (expression)
    double offset = 0.0; ///< added after the factor (expression; 273.15 for a bare degC value)
    /// Where the expression was written (its statement's start, the expression; both empty when
    /// unknown): a run that finds it out of range or not finite names that place, which for a
    /// case's override is the case's line, not the element's declaration.
    Span at, mark;
  };
  double constant = 0.0; ///< value when kind() == constant

  /// A constant 0.
  Signal() = default;
  /// A copy sharing the other's corners.
  Signal(const Signal& other) : constant(other.constant), shape_(other.shape_) {}
  /// Takes another signal's corners.
  Signal(Signal&& other) noexcept : constant(other.constant), shape_(std::move(other.shape_)) {}
  /// Becomes a copy of another signal, sharing its corners.
  Signal& operator=(const Signal& other);
  /// Takes another signal's corners.
  Signal& operator=(Signal&& other) noexcept;

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
  bool is_constant() const { return kind() == Kind::constant; }
  /// True when the value is linear in the time between its corners (every kind but an expression
  /// that multiplies varying terms or takes a function of one).
  bool piecewise_linear() const;
  /// The shape: constant unless corners or an expression were made.
  Kind kind() const { return shape_ ? shape_->kind : Kind::constant; }
  /// Corner times, increasing (empty for a constant; for an expression, those of the signals it
  /// reads).
  const std::vector<double>& times() const;
  /// Values at the corners (empty for a constant or an expression).
  const std::vector<double>& values() const;
  /// The signal as text in SI numbers, for messages (`pwl(0: 293.15, 60: 300)`, an expression's
  /// program).
  std::string text() const;
  /// True when both signals have the same value at every time (same kind, corners and program).
  bool same_as(const Signal& other) const;
  /// Times where the signal jumps or bends (where an integrator should restart).
  const std::vector<double>& corners() const { return times(); }
  /// The corners and expression, made (empty, of kind constant) on first use, to be filled in or
  /// changed: this signal's own (copied first where other signals share them).
  Shape& shape();
  /// The corners and expression, made (empty) on first use, of a signal that becomes of a kind
  /// (this signal's own, as shape()).
  Shape& shape(Kind kind);
  /// The corners and expression, or nullptr if none were made.
  const Shape* shape_if() const { return shape_.get(); }
  /// Multiplies every value by a factor.
  Signal scaled(double factor) const;

private:
  boost::intrusive_ptr<Shape> shape_;
  /// The corner after the last reading (a hint for the next: readings mostly move forward);
  /// atomic, as an expression's signals are shared by the threads that read it, and the signal's
  /// own, so that threads reading copies of a shared table do not move each other's.
  mutable std::atomic<std::size_t> hint_{0};
};

} // namespace thermnet::lang
