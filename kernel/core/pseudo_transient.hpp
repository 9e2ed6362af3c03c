#pragma once
/// A walk toward a steady state that Newton's method cannot reach from its guess: the heat
/// balance integrated in pseudo-time with inputs held, from which Newton then converges.

#include "kernel/core/solver_types.hpp"
#include "kernel/core/thermal_system.hpp"

#include <vector>

namespace thermnet::detail {

class SystemEvaluator;

/// Integrates c_i dT_i/dtau = F_i(t, T) of the evaluator's system with the inputs held at time t
/// and pseudo-capacities c_i = |dF_i/dT_i| at the guess times 1 s (every unknown relaxes in about
/// a second, massless ones included) until the unknowns settle; T is the guess on entry and the
/// end point on exit.
/// Returns false (T unchanged) when the walk fails (no steady state, or one below 0 K).
bool pseudo_transient(SystemEvaluator& ev, std::vector<double>& T, double t,
                      const SolverOptions& opt);

} // namespace thermnet::detail
