// Optimizer plugin 'mc': the aerial-camera study's Monte Carlo parameter correction — uniform
// samples in the ranges, kept only within the tolerance everywhere, lowest RMSE wins.

#include "kernel/calibration/optimizer.hpp"
#include "kernel/calibration/sample_search.hpp"
#include "kernel/core/parallel.hpp"

namespace thermnet {
namespace {

/// Uniform random sampling; sample i depends only on (seed, N, i): N samples are N fresh draws for
/// the seed (the study's 3000/6000/12000 are independent sets, so 2N never contains N).
class MonteCarlo final : public Optimizer {
public:
  OptimizerResult run(const CalibrationProblem& problem,
                      const OptimizerSettings& settings) override {
    const std::size_t n = settings.samples > 0 ? settings.samples : default_sample_count;
    const std::vector<double> lo = problem.lower(), hi = problem.upper();
    const std::uint64_t seed = derived_seed(settings.seed, n);
    return sample_search(problem, settings, "mc", n,
                         [&](std::size_t i) { return uniform_point(lo, hi, seed, i); });
  }
};

OptimizerPlugin make_mc() {
  return {.name = "mc",
          .doc = "the study's Monte Carlo: N fresh uniform samples for the seed (N and 2N are "
                 "independent sets), a sample is kept only if every point is within --tolerance "
                 "(5 K), the kept one with the lowest RMSE wins",
          .create = [] { return std::make_unique<MonteCarlo>(); },
          .budget = "samples (3000)"};
}

} // namespace

THERMNET_REGISTER(OptimizerPlugin, make_mc);

} // namespace thermnet
