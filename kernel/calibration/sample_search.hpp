#pragma once
/// The sampling search of the aerial-camera study (mc, lhs): evaluate sample points in parallel,
/// keep those within the tolerance, the lowest RMSE wins.

#include "kernel/calibration/optimizer.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace thermnet {

/// Default number of samples of the sampling methods (the study's smallest run).
inline constexpr std::size_t default_sample_count = 3000;

/// Point i of a uniform Monte Carlo design in [lo, hi]: coordinate j is uniform01(seed, j, i), so
/// it depends only on (seed, i).
std::vector<double> uniform_point(const std::vector<double>& lo, const std::vector<double>& hi,
                                  std::uint64_t seed, std::size_t i);

/// A Latin hypercube of n points in [lo, hi] built from the seed alone: in each dimension every
/// one of the n equal strata holds exactly one point, placed uniformly inside it.
std::vector<std::vector<double>> latin_hypercube(std::size_t n, const std::vector<double>& lo,
                                                 const std::vector<double>& hi, std::uint64_t seed);

/// Evaluates point(i) for i in [0, n) on settings.threads workers with the acceptance rule of the
/// study (every |T_sim - T_meas| < settings.tolerance, evaluations abandoned at the first
/// violation); the accepted point with the lowest RMSE wins, ties going to the lower index, so
/// the result does not depend on the thread count. `point` must be thread-safe and depend on i
/// only. Honours settings.cancel (the best so far is returned, `cancelled` set) and reports
/// progress after each evaluation through settings.on_progress (called from worker threads).
OptimizerResult sample_search(const CalibrationProblem& problem, const OptimizerSettings& settings,
                              std::string method, std::size_t n,
                              const std::function<std::vector<double>(std::size_t)>& point);

} // namespace thermnet
