#pragma once
/// The guard against temperatures below absolute zero: found in a state, reported with the node,
/// the time and what usually causes it.

#include "kernel/core/system_evaluator.hpp"

namespace thermnet::detail {

/// The unknown with the lowest temperature below 0 K among the n values of T, or -1 if none is.
int coldest_below_absolute_zero(const double* T, int n);

/// Where a temperature below 0 K was met.
struct BelowAbsoluteZero {
  int unknown;     ///< the unknown (node)
  double crossing; ///< time it crossed 0 K (a steady state: the time of its inputs), s
  double kelvin;   ///< its temperature at time `reached`, K (< 0)
  double reached;  ///< time of that temperature, s
  bool steady;     ///< found by the steady solver rather than during a run
};

/// Throws SolverError naming the node, the times and the usual causes, as a failure of `call`.
[[noreturn]] void fail_below_absolute_zero(const SystemEvaluator& ev, const BelowAbsoluteZero& b,
                                           const char* call);

} // namespace thermnet::detail
