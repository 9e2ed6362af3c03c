#pragma once
/// One run of a case checked against the model's requirements (check, design): the outcomes, the
/// per-source energy and duty (kernel energy accounting), and the kept columns for a plot.

#include "kernel/core/requirement_check.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/model.hpp"

#include <memory>
#include <string>
#include <vector>

namespace thermnet::app {

/// A run of one case and what its requirements show.
struct CheckedRun {
  std::unique_ptr<Network> net;             ///< the network run (owns the spec outcomes point to)
  std::vector<RequirementOutcome> outcomes; ///< one per requirement of the case
  EnergyTotals energy;                      ///< per-element energy, on time, switches
  SimulationResult kept;                    ///< the kept columns (keep_nodes) over time
  /// The smallest slack relative to each requirement's scale (negative: violated).
  bool met() const;
};

/// Runs case `case_name` with `params` (overrides of ranged or fixed params), checking every
/// requirement that applies to it; keeps the columns of the nodes `keep` names (names or globs,
/// none when empty). Throws ModelError, SolverError.
CheckedRun run_checked(const lang::Model& model, const std::string& case_name,
                       const lang::ParamValues& params, const SimulationOptions& options,
                       const std::vector<std::string>& keep = {});

} // namespace thermnet::app
