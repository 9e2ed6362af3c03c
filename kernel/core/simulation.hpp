#pragma once
/// Running a case: initial state, transient or steady solve, samples at the output times.

#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"

#include <optional>
#include <vector>

namespace thermnet {

/// What to run.
struct SimulationOptions {
  std::optional<double> duration; ///< overrides the case's duration, s
  std::optional<double> output;   ///< overrides the case's output interval or listed times, s
  bool steady = false;            ///< solve the steady state at t = 0 instead of a transient
  SolverOptions solver;           ///< tolerances and linear solver
};

/// Temperatures of every node (nodes and boundaries, spec order) at each output time, in K.
struct SimulationResult {
  std::vector<std::string> names;         ///< node names, spec order
  std::vector<double> times;              ///< output times, s
  std::vector<std::vector<double>> temps; ///< temps[k][i]: node i at times[k], K
  SolverStats stats;                      ///< solver counters (transient or steady)
};

/// The output times of a run: 0, dt, 2 dt, ... and the end time exactly.
std::vector<double> output_times(double duration, double interval);

/// Simulates a network; throws SolverError on solver failure and std::invalid_argument on bad
/// options.
SimulationResult simulate(Network& net, const SimulationOptions& opt = {});

} // namespace thermnet
