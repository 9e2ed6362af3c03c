// Optimizer plugin 'mc': the aerial-camera study's Monte Carlo parameter correction — uniform
// samples in the ranges, kept only within the tolerance everywhere, lowest RMSE wins.

#include "kernel/calibration/optimizer.hpp"
#include "kernel/calibration/sample_search.hpp"

namespace thermnet {
namespace {

/// Uniform random sampling; sample i depends only on (seed, i).
class MonteCarlo final : public Optimizer {
public:
  OptimizerResult run(const CalibrationProblem& problem,
                      const OptimizerSettings& settings) override {
    const std::size_t n = settings.samples > 0 ? settings.samples : default_sample_count;
    const std::vector<double> lo = problem.lower(), hi = problem.upper();
    return sample_search(problem, settings, "mc", n,
                         [&](std::size_t i) { return uniform_point(lo, hi, settings.seed, i); });
  }
};

OptimizerPlugin make_mc() {
  return {.name = "mc",
          .doc = "the study's Monte Carlo: uniform samples, a sample is kept only if every point "
                 "is within "
                 "--tolerance (5 K), the kept one with the lowest RMSE wins",
          .create = [] { return std::make_unique<MonteCarlo>(); },
          .budget = "samples (3000)"};
}

} // namespace

THERMNET_REGISTER(OptimizerPlugin, make_mc);

} // namespace thermnet
