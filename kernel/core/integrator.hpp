#pragma once
/// Transient (CVODE BDF, or IDA when algebraic nodes exist) and steady-state (KINSOL) solution of a
/// ThermalSystem.

#include "kernel/core/solver_types.hpp"
#include "kernel/core/thermal_system.hpp"

#include <functional>
#include <vector>

namespace thermnet {

/// Receives the solution at each requested output time (T in kelvin, one per unknown).
using OutputCallback = std::function<void(double t, const std::vector<double>& T)>;

/// Integrates from t0 to t1; T holds the initial state on entry and the final state on exit.
/// `out` is called at every time of `output_times` (sorted, within [t0, t1]) using dense output.
SolverStats integrate(ThermalSystem& sys, std::vector<double>& T, double t0, double t1,
                      const std::vector<double>& output_times, const OutputCallback& out,
                      const SolverOptions& opt = {});

/// Solves the steady state F(t, T) = 0 by Newton's method with line search (KINSOL); T is the guess
/// on entry.
SolverStats solve_steady(ThermalSystem& sys, std::vector<double>& T, double t,
                         const SolverOptions& opt = {});

} // namespace thermnet
