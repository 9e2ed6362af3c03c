#pragma once
/// Values that depend on the simulation time, written as expressions of the model
/// (`T = 20 - 0.02 * time`): compiled once into a small stack program, evaluated at any time.

#include "lang/ast.hpp"
#include "lang/signal.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace thermnet::lang {

/// An expression of the time `t` (in s) whose every other name is already a number, in SI; the
/// signals standing in it (step, pwl, table, another element's key) are kept whole and evaluated
/// at `t`.
class TimeProgram {
public:
  /// One instruction of the postfix program.
  struct Op {
    /// What the instruction does.
    enum class Code : std::uint8_t {
      constant,
      time,
      negate,
      add,
      subtract,
      multiply,
      divide,
      power,
      exp,
      log,
      log10,
      sin,
      cos,
      tan,
      sqrt,
      abs,
      min,
      max,
      signal
    };
    Code code = Code::constant; ///< the operation
    std::uint32_t count = 0;    ///< number of arguments of min and max; index of a signal
    double value = 0;           ///< the constant
  };

  /// The value at time t (s).
  double at(double t) const;
  /// The expression with every name replaced by its value, for messages and rewritten models
  /// (fully parenthesised: `(20 - (0.02 * time))`).
  std::string text() const;

  std::vector<Op> ops;         ///< the program, in postfix order
  std::size_t max_depth = 0;   ///< deepest stack it needs
  std::vector<Signal> signals; ///< the signals the program reads (Code::signal)
  /// The times where one of its signals jumps or bends, sorted, without repeats.
  std::vector<double> corners() const;
  /// True when its value is linear in the time between its corners (sums, differences and
  /// constant multiples of the time and of step, pwl and table signals), so that two readings
  /// inside an interval between corners give it everywhere there.
  bool piecewise_linear() const;
};

/// Compiles the expression rooted at `root` of `file`: `time` stays the time, every other name is
/// replaced by `value_of(name)` (SI), a number with a unit by its SI value, a signal or key
/// reference by `signal_of(node)`. The expression must already have been evaluated once (which
/// checked its names, units and functions).
std::shared_ptr<const TimeProgram>
compile_time_program(const ast::File& file, ast::Index root,
                     const std::function<double(const ast::Identifier&)>& value_of,
                     const std::function<Signal(ast::Index node)>& signal_of = nullptr);

} // namespace thermnet::lang
