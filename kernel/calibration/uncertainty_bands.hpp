#pragma once
/// Uncertainty bands: the ranged params drawn uniformly, one simulation per sample, and per node
/// the min, chosen percentiles and max of the temperature at every output time.

#include "kernel/core/simulation.hpp"
#include "lang/model.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace thermnet {

/// What to sample.
struct UncertaintyOptions {
  std::size_t samples = 100;                  ///< number of draws
  std::uint64_t seed = 1;                     ///< draw i of param j is uniform01(seed, j, i)
  std::vector<double> percentiles{5, 50, 95}; ///< percentiles to report, in (0, 100)
  int threads = 0;                            ///< worker threads (0: all cores)
  SimulationOptions simulation;               ///< duration/output overrides and solver settings
};

/// Per node and output time: min, percentiles, max over the samples that could be simulated.
struct UncertaintyBands {
  std::vector<std::string> names;  ///< node and boundary names, spec order (then sensors)
  std::vector<double> times;       ///< output times, s
  std::vector<double> percentiles; ///< the reported percentiles
  /// stats[i][k][q]: node i at times[k]; q = 0 min, 1..P the percentiles, P + 1 max (K).
  std::vector<std::vector<std::vector<double>>> stats;
  SimulationResult nominal;        ///< the run with the declared values
  std::size_t samples = 0;         ///< samples drawn
  std::size_t failed = 0;          ///< samples whose simulation failed (left out)
  std::vector<std::string> params; ///< the ranged params that were drawn
};

/// Draws the ranged params of a case and simulates each sample (in parallel; the result does
/// not depend on the number of threads); throws lang::ModelError, SolverError if the nominal
/// run fails, std::invalid_argument for bad options, std::runtime_error when no sample can be
/// simulated.
UncertaintyBands run_uncertainty(const lang::Model& model, const std::string& case_name,
                                 const UncertaintyOptions& options);

/// Percentile q (0..100) of sorted values, linear interpolation between order statistics.
double percentile_of_sorted(const std::vector<double>& sorted, double q);

} // namespace thermnet
