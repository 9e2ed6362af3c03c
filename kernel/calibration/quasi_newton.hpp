#pragma once
/// A bounded quasi-Newton minimiser of a smooth scalar function (a negative log-likelihood): BFGS
/// with a backtracking line search, in unbounded coordinates z = logit(u) of each parameter's box
/// mapped onto [0, 1] (linear or log scale, as the least-squares core's WorkingCoordinates), so
/// every trial point lies inside the box. Gradients by differences in z, evaluated in parallel:
/// forward while far from the minimum, central near it and before any stop; deterministic whatever
/// the number of threads.

#include "kernel/calibration/least_squares.hpp"

#include <Eigen/Dense>

#include <functional>
#include <vector>

namespace thermnet {

/// The function to minimise at x (inside the box); +inf or NaN where it cannot be evaluated.
/// Called from several threads at once.
using ScalarObjective = std::function<double(const std::vector<double>& x)>;

/// When to stop.
struct QuasiNewtonOptions {
  int max_iterations = 200; ///< most BFGS iterations
  double ftol = 1e-9;       ///< stop when an iteration lowers f by less than ftol (1 + |f|)
  double gtol = 1e-6;       ///< stop when every |df/dz| is below this
  double step = 1e-4;       ///< difference step in z
  int threads = 1;          ///< gradient components in parallel (0: all cores)
};

/// The outcome of a minimisation.
struct QuasiNewtonResult {
  bool ok = false;             ///< the start could be evaluated
  std::vector<double> x;       ///< the best point
  double f = 0.0;              ///< f there
  int iterations = 0;          ///< BFGS iterations
  std::size_t evaluations = 0; ///< evaluations of f
  bool converged = false;      ///< stopped by ftol or gtol (not by the iteration limit)
};

/// Minimises f within the box of `params` from `start` (clamped a little inside the box).
QuasiNewtonResult minimise_bounded(const ScalarObjective& f,
                                   const std::vector<BoundedParam>& params,
                                   const std::vector<double>& start,
                                   const QuasiNewtonOptions& options = {});

/// The Hessian of f at x in the scaled coordinates y (x for linear params, ln x for log ones) by
/// central differences of relative step `step` of each param's box width in y; NaN entries where
/// f failed. Evaluations run in parallel.
Eigen::MatrixXd scaled_hessian(const ScalarObjective& f, const std::vector<BoundedParam>& params,
                               const std::vector<double>& x, double step, int threads);

} // namespace thermnet
