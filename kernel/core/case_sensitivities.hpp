#pragma once
/// A case simulated with the forward sensitivities of chosen nodes' temperatures to parameters,
/// each parameter given as the network elaborated with it moved (NetworkDerivatives).

#include "kernel/core/network_derivatives.hpp"
#include "kernel/core/solver_types.hpp"

#include <optional>
#include <string>
#include <vector>

namespace thermnet {

/// Temperatures of chosen nodes at chosen times and their derivatives with respect to parameters.
struct NodeSensitivities {
  std::vector<std::vector<double>> T;               ///< T[k][i]: node i of the list at time k, K
  std::vector<std::vector<std::vector<double>>> dT; ///< dT[j][k][i]: its derivative by p_j
  SolverStats stats;                                ///< the solver's counters
};

/// Simulates `spec` from its start state (start_state()) to the last of `times` (sorted, >= 0)
/// with the sensitivities along each moved spec, and samples the `nodes` (spec indices, boundaries
/// allowed) at `times`. A parameter that moves nothing gets zero sensitivities without being
/// integrated. Returns nullopt, with the reason in `why_not`, when the network cannot integrate
/// sensitivities (NetworkDerivatives::why_not()); throws SolverError when the simulation fails.
std::optional<NodeSensitivities>
simulate_sensitivities(lang::NetworkSpec spec, std::vector<MovedSpec> moved,
                       const std::vector<double>& times, const std::vector<int>& nodes,
                       const SolverOptions& solver, std::string* why_not = nullptr);

} // namespace thermnet
