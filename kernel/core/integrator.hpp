#pragma once
/// Transient (CVODE BDF, or IDA when algebraic nodes exist) and steady-state (KINSOL) solution of a
/// ThermalSystem.

#include "kernel/core/parameter_derivatives.hpp"
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

/// Receives the solution and its forward sensitivities at each output time: T (one per unknown)
/// and S[j] = dT/dp_j (one vector per parameter).
using SensitivityCallback = std::function<void(double t, const std::vector<double>& T,
                                               const std::vector<std::vector<double>>& S)>;

/// integrate() with the forward sensitivities of the parameters of `d` (CVODES): S holds
/// dT/dp_j at t0 on entry (one vector per parameter) and at t1 on exit, and `out` receives them
/// with the state. The steps are those integrate() takes without sensitivities. Throws
/// std::invalid_argument when the system switches by events or has arithmetic nodes.
SolverStats integrate(ThermalSystem& sys, ParameterDerivatives& d, std::vector<double>& T,
                      std::vector<std::vector<double>>& S, double t0, double t1,
                      const std::vector<double>& output_times, const SensitivityCallback& out,
                      const SolverOptions& opt = {});

/// Solves the steady state F(t, T) = 0 by Newton's method with line search (KINSOL); T is the guess
/// on entry.
SolverStats solve_steady(ThermalSystem& sys, std::vector<double>& T, double t,
                         const SolverOptions& opt = {});

} // namespace thermnet
