// Optimizer plugin 'lhs': the study's Monte Carlo selection over a Latin hypercube design.

#include "kernel/calibration/optimizer.hpp"
#include "kernel/calibration/sample_search.hpp"

namespace thermnet {
namespace {

/// Latin hypercube sampling: the whole design is built from the seed first, then evaluated.
class LatinHypercube final : public Optimizer {
public:
  OptimizerResult run(const CalibrationProblem& problem,
                      const OptimizerSettings& settings) override {
    const std::size_t n = settings.samples > 0 ? settings.samples : default_sample_count;
    const auto design = latin_hypercube(n, problem.lower(), problem.upper(), settings.seed);
    return sample_search(problem, settings, "lhs", n, [&](std::size_t i) { return design[i]; });
  }
};

OptimizerPlugin make_lhs() {
  return {.name = "lhs",
          .doc = "the same as mc with Latin hypercube samples",
          .create = [] { return std::make_unique<LatinHypercube>(); },
          .budget = "samples (3000)"};
}

} // namespace

THERMNET_REGISTER(OptimizerPlugin, make_lhs);

} // namespace thermnet
