#pragma once
/// Energy accounting of a transient: every element's heat into each of its terminals and each
/// thermostat's on-time integrated as extra states beside the temperatures (same tolerances, exact
/// switching times), with the thermostats' switch counts.

#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"

#include <vector>

namespace thermnet {

/// What went where over a transient from t0 to t1.
struct EnergyTotals {
  double t0 = 0.0;                                 ///< start, s
  double t1 = 0.0;                                 ///< end, s
  std::vector<double> T_start;                     ///< every node at t0 (spec order), K
  std::vector<double> T_end;                       ///< every node at t1 (spec order), K
  std::vector<std::vector<double>> element_energy; ///< [e][j]: heat into terminal j of element e, J
  std::vector<double> on_time;                     ///< per element: time delivering heat, s
  std::vector<int> switches;                       ///< per element: on/off changes by events
  std::vector<char> switching;                     ///< per element: 1 when it switches by events
};

/// Like integrate(), also accumulating `totals` (T holds the unknowns; the callback gets them).
SolverStats integrate_with_energy(Network& net, std::vector<double>& T, double t0, double t1,
                                  const std::vector<double>& output_times,
                                  const OutputCallback& out, const SolverOptions& opt,
                                  EnergyTotals& totals);

} // namespace thermnet
