#pragma once
/// The search of `thermnet design`: the ranged params chosen so that every requirement of every
/// case is met at the least heater energy (or installed power). A penalty formulation: the
/// objective relative to its value at the start plus 100 x the normalised violations, minimised
/// by a seeded sample of the ranges (evaluated in parallel, stored by index) followed by pagmo2's
/// compass search from the best sample, serially: the same seed gives the same result whatever
/// the thread count.

#include "app/checked_run.hpp"

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace thermnet::app {

/// What the design minimises.
enum class DesignObjective {
  energy, ///< heat supplied by every source, summed over the cases, J
  power   ///< installed power: the sum of the sources' constant `P`, W (the largest over cases)
};

/// One evaluated design point.
struct DesignPoint {
  std::vector<double> x;  ///< param values, SI
  bool ok = false;        ///< every case ran
  std::string failure;    ///< why a case did not run
  double objective = 0.0; ///< energy (J) or installed power (W)
  double violation = 0.0; ///< sum of normalised violations (0: feasible with the safety margin)
  bool feasible = false;  ///< every requirement met (slack >= 0)
};

/// The design problem: the model, the params chosen, the cases and what is minimised.
class DesignProblem {
public:
  /// A problem over `params` (ranged params of `model`) and the resolved `cases`.
  DesignProblem(const lang::Model& model, std::vector<lang::ParamInfo> params,
                std::vector<std::string> cases, DesignObjective objective,
                SimulationOptions options);
  /// The params chosen.
  const std::vector<lang::ParamInfo>& params() const { return params_; }
  /// The cases run.
  const std::vector<std::string>& cases() const { return cases_; }
  /// The param values of x, by name (the model's other params as declared).
  lang::ParamValues values(const std::vector<double>& x) const;
  /// Runs every case at x (keeping `keep`'s columns); throws ModelError, SolverError.
  std::vector<CheckedRun> run(const std::vector<double>& x,
                              const std::vector<std::string>& keep = {}) const;
  /// Evaluates x (never throws: a failed run is a point that is not ok).
  DesignPoint evaluate(const std::vector<double>& x) const;
  /// The objective and violations of finished runs.
  DesignPoint score(const std::vector<double>& x, const std::vector<CheckedRun>& runs) const;
  /// The objective of a point, in the unit reports use ("J" or "W").
  DesignObjective objective() const { return objective_; }

private:
  const lang::Model& model_;
  std::vector<lang::ParamInfo> params_;
  std::vector<std::string> cases_;
  DesignObjective objective_;
  SimulationOptions options_;
};

/// How to search.
struct DesignSettings {
  std::size_t samples = 0;     ///< seeded samples of the ranges before the local search
  std::size_t evaluations = 0; ///< budget of the compass search
  std::uint64_t seed = 1;      ///< seed of the samples
  int threads = 0;             ///< workers of the sample stage (0: all cores)
  const std::atomic<bool>* cancel = nullptr; ///< set to stop early
};

/// The best point found and how many were evaluated.
struct DesignResult {
  DesignPoint best;            ///< the best point (feasible first, then least objective)
  std::size_t evaluations = 0; ///< points evaluated
  std::size_t failed = 0;      ///< points whose runs failed
};

/// Searches the ranges: samples, then compass search from the best of them and the declared
/// values.
DesignResult design_search(const DesignProblem& problem, const DesignSettings& settings);

} // namespace thermnet::app
