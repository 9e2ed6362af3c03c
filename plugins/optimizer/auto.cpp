// Optimizer plugin 'auto': a global start by Latin hypercube sampling, then Levenberg-Marquardt.
//
// Stage 1 runs the registered 'lhs' plugin with 20 samples per dimension (at least 20) and no
// tolerance rejection (a tolerance of 1e300 K keeps every simulated sample), so the best sample
// of the box is found even when no sample is within the study's 5 K. With `samples` given, the
// lhs stage gets min(20 p, samples / 2) and lm the rest. Stage 2 runs the registered 'lm'
// plugin from the best sample (or from the declared values if lhs found nothing). The result is
// lm's point and statistics; evaluations, simulations and wall time add up both stages, and
// the notes of both stages are kept. Deterministic because both stages are.

#include "kernel/calibration/optimizer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace thermnet {
namespace {

OptimizerResult run_stage(const std::string& name, const CalibrationProblem& problem,
                          const OptimizerSettings& settings) {
  const OptimizerPlugin* plugin = OptimizerRegistry::global().find(name);
  if (!plugin) throw std::logic_error("auto: optimizer '" + name + "' is not registered");
  return plugin->create()->run(problem, settings);
}

class AutoOptimizer final : public Optimizer {
public:
  OptimizerResult run(const CalibrationProblem& problem, const OptimizerSettings& s) override {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t p = problem.dimension();
    std::size_t global_samples = std::max<std::size_t>(20, 20 * p);
    if (s.samples > 0)
      global_samples = std::max<std::size_t>(1, std::min(global_samples, s.samples / 2));

    OptimizerSettings global = s;
    global.samples = global_samples;
    global.tolerance = 1e300;
    OptimizerResult first = run_stage("lhs", problem, global);

    OptimizerSettings local = s;
    local.samples = s.samples > 0 ? std::max<std::size_t>(p + 2, s.samples - first.evaluations) : 0;
    if (first.found) local.start = first.best;
    OptimizerResult r = first.cancelled ? first : run_stage("lm", problem, local);

    r.method = "auto";
    if (!first.cancelled) {
      r.samples += first.samples;
      r.evaluations += first.evaluations;
      r.simulations += first.simulations;
      r.accepted += first.accepted;
    }
    if (first.found && !r.found) { // lm could not improve or start: keep the lhs best
      r.found = true;
      r.best = first.best;
      r.rmse = first.rmse;
      r.r2 = first.r2;
    }
    std::vector<std::string> notes;
    notes.push_back(fmt::format(
        "auto: lhs with {} samples ({} evaluations, best RMSE {}), then lm from {}", global_samples,
        first.evaluations, first.found ? fmt::format("{:.4g} K", first.rmse) : std::string("none"),
        first.found ? "the best sample" : "the declared values"));
    notes.insert(notes.end(), first.notes.begin(), first.notes.end());
    if (!first.cancelled) notes.insert(notes.end(), r.notes.begin(), r.notes.end());
    r.notes = std::move(notes);
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }
};

OptimizerPlugin make_auto() {
  return {.name = "auto",
          .doc = "lhs with 20 samples per param (no tolerance rejection) as a global start, then "
                 "lm from the "
                 "best sample",
          .create = [] { return std::make_unique<AutoOptimizer>(); },
          .budget = "split: lhs min(20 p, N/2), lm the rest"};
}

} // namespace
THERMNET_REGISTER(OptimizerPlugin, make_auto);
} // namespace thermnet
