#pragma once
/// Optimizer plugins: value types over the CalibrationProblem (in the manner of pagmo2's
/// algorithms).

#include "kernel/calibration/calibration_problem.hpp"
#include "kernel/core/registry.hpp"

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace thermnet {

/// Progress of a run, reported after each completed evaluation (from any thread).
struct Progress {
  std::size_t done = 0;   ///< evaluations completed
  std::size_t total = 0;  ///< evaluations planned (0 if unknown)
  double best_rmse = 0.0; ///< best RMSE so far, K (NaN before the first accepted point)
};

/// Settings shared by every optimizer.
struct OptimizerSettings {
  std::size_t samples = 0;   ///< samples / budget (0: the method's default)
  double tolerance = 5.0;    ///< mc/lhs acceptance limit |T_sim - T_meas|, K
  std::uint64_t seed = 1;    ///< random seed: same seed, same result, whatever the threads
  int threads = 0;           ///< worker threads (0: all cores)
  std::vector<double> start; ///< starting point for local methods (empty: the declared values)
  SolverOptions solver;      ///< simulation tolerances
  std::function<void(const Progress&)> on_progress; ///< progress callback (may be empty)
  const std::atomic<bool>* cancel = nullptr; ///< set to stop early; the best so far is returned
};

/// The outcome of a run: a row of the study's Table 3, plus what local methods know.
struct OptimizerResult {
  std::string method;             ///< method name
  std::size_t samples = 0;        ///< samples drawn (or population x generations)
  std::size_t evaluations = 0;    ///< full or partial evaluations of the problem
  std::size_t simulations = 0;    ///< case simulations started
  std::size_t accepted = 0;       ///< samples within the tolerance (mc/lhs)
  bool found = false;             ///< a best point exists
  std::vector<double> best;       ///< best point (SI)
  double rmse = 0.0;              ///< its RMSE, K
  double r2 = 0.0;                ///< its R^2 (NaN: undefined, the measured data do not vary)
  double wall_s = 0.0;            ///< wall time, s
  bool cancelled = false;         ///< stopped early by the cancel flag
  std::vector<double> std_errors; ///< standard errors of the params (least squares; SI)
  std::vector<std::vector<double>>
      correlation;                ///< correlation matrix of the params (least squares)
  std::vector<std::string> notes; ///< remarks for the report (e.g. "no sample accepted")
};

/// A calibration method.
class Optimizer {
public:
  virtual ~Optimizer() = default;
  /// Runs the method on the problem.
  virtual OptimizerResult run(const CalibrationProblem& problem,
                              const OptimizerSettings& settings) = 0;
};

/// A named optimizer kind with a one-line doc and a factory.
struct OptimizerPlugin {
  static constexpr const char* family = "optimizer";  ///< registry family name
  std::string name;                                   ///< e.g. "mc"
  std::string doc;                                    ///< one line for --help
  std::function<std::unique_ptr<Optimizer>()> create; ///< factory
  std::string budget; ///< what --samples counts for it, and the default (docs, `thermnet kinds`)
};

/// All optimizer kinds.
using OptimizerRegistry = Registry<OptimizerPlugin>;

} // namespace thermnet
