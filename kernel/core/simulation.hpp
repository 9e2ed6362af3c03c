#pragma once
/// Running a case: initial state, transient or steady solve, samples at the output times.

#include "kernel/core/energy_account.hpp"
#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/row_matrix.hpp"

#include <functional>
#include <optional>
#include <vector>

namespace thermnet {

/// What to run.
struct SimulationOptions {
  std::optional<double> duration; ///< overrides the case's duration, s
  std::optional<double> output;   ///< overrides the case's output interval or listed times, s
  bool steady = false;            ///< solve the steady state at t = 0 instead of a transient
  /// Append each sensor's reading (K, Network::sensor_elements() order) to every row, after the
  /// nodes and boundaries.
  bool sensors = false;
  SolverOptions solver; ///< tolerances and linear solver
};

/// Temperatures of every node (nodes and boundaries, spec order) at each output time, in K.
struct SimulationResult {
  std::vector<std::string> names; ///< node names, spec order (then sensors, if asked)
  std::vector<double> times;      ///< output times, s
  RowMatrix temps;                ///< temps[k][i]: node i at times[k], K
  SolverStats stats;              ///< solver counters (transient or steady)
};

/// The state at t = 0 of a case, for every command that runs one: the nodes' T0 (else the case's
/// initial, else 20 degC); with `initial = steady`, the steady state at t = 0 with every thermostat
/// (switch) in the state consistent with it. Event states (heaters on/off) are left set in `net`
/// so that the transient starts from the same state; throws SolverError when the steady state does
/// not converge or a thermostat has none (it cycles). Adds the steady solve's counters to `stats`.
std::vector<double> start_state(Network& net, const SolverOptions& solver,
                                SolverStats* stats = nullptr);

/// The output times of a run: 0, dt, 2 dt, ... and the end time exactly.
std::vector<double> output_times(double duration, double interval);

/// Receives one output row: its time (s) and the temperature of every node and boundary (spec
/// order), K.
using RowCallback = std::function<void(double t, const std::vector<double>& temps)>;

/// Simulates a network; throws SolverError on solver failure and std::invalid_argument on bad
/// options.
SimulationResult simulate(Network& net, const SimulationOptions& opt = {});

/// Like simulate(), but hands each row to `row` as soon as it is computed instead of keeping it
/// (a large network's whole result need not fit in memory); returns the solver counters. With
/// `energy`, a transient also integrates every element's heat and each thermostat's on-time into it
/// (a steady state leaves it empty).
SolverStats simulate(Network& net, const SimulationOptions& opt, const RowCallback& row,
                     EnergyTotals* energy = nullptr);

} // namespace thermnet
