#pragma once
/// The guard on inputs computed while a run goes on (expressions of the time and of signals): a
/// value that leaves its key's valid range (a boundary below 0 K, a switch outside [0, 1], a
/// negative thermostat power) or is not finite stops the run at the statement that wrote it, with
/// the time. Step, pwl and table values are all checked when the model is read.

#include "lang/network_spec.hpp"

#include <string>
#include <vector>

namespace thermnet {

/// The expression-valued inputs of a network, checked at any time.
class InputCheck {
public:
  /// Collects the boundary temperatures and element keys of `spec` that are expressions.
  explicit InputCheck(const lang::NetworkSpec& spec);
  /// True when there is nothing to check.
  bool empty() const { return inputs_.empty(); }
  /// Throws lang::ModelError (located at the statement, naming the value and the time) when an
  /// input of `spec` (the one it was built from) is out of its range or not finite at time t.
  void at(const lang::NetworkSpec& spec, double t) const;
  /// Throws lang::ModelError (located at the expression) when an input of `spec` grows without
  /// bound near time t (a pole: tan(time / 100) at t = 157.08 s), which the integrators, failing
  /// there, cannot name; a run of [t0, t) gives the values it is compared with.
  void unbounded_near(const lang::NetworkSpec& spec, double t, double t0) const;

private:
  struct Input {
    int node = -1;                        // a boundary's temperature, or
    int element = -1;                     // an element's key
    const lang::KeySchema* key = nullptr; // its schema (the range)
  };
  std::vector<Input> inputs_;
};

} // namespace thermnet
