#pragma once
/// The one bounded least-squares core: a residual problem with box bounds, a projected
/// Levenberg-Marquardt solver and the linearised covariance of its estimate. The `lm` optimizer
/// and the diagnosis fits both use it.
///
/// Working coordinates. Every parameter is stepped in its box mapped onto [0, 1]: u = (x - lo) /
/// (hi - lo), or (ln x - ln lo) / (ln hi - ln lo) for a log-scaled one (wide positive ranges).
/// The damping is Marquardt's (proportional to the diagonal of JᵀJ), so the steps do not depend on
/// the units; only the finite-difference step and `xtol` are fractions of that box.

#include <Eigen/Dense>

#include <atomic>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace thermnet {

/// How a parameter is stepped: in its value or in its logarithm (positive, wide ranges).
enum class ParamScale { linear, log };

/// One parameter's box and scale.
struct BoundedParam {
  double lo = 0.0;                       ///< lower bound
  double hi = 1.0;                       ///< upper bound (>= lo)
  ParamScale scale = ParamScale::linear; ///< log needs lo > 0
};

/// Residuals r(x) to be made small in the least-squares sense, x within a box.
class ResidualProblem {
public:
  virtual ~ResidualProblem() = default;
  /// The parameters (the dimensions of x), in order.
  virtual const std::vector<BoundedParam>& params() const = 0;
  /// The residuals at x (inside the box); false when x cannot be evaluated. Called from several
  /// threads at once when the Jacobian's columns run in parallel.
  virtual bool residuals(const std::vector<double>& x, std::vector<double>& r) const = 0;
  /// Forward-difference step of parameter j at x, as a fraction of its box (default 1e-3).
  virtual double difference_step(std::size_t j, const std::vector<double>& x) const;
  /// What residuals_and_jacobian() evaluated.
  enum class Evaluated {
    nothing,   ///< x cannot be evaluated
    residuals, ///< the residuals only (the solver differences them for the Jacobian)
    both       ///< the residuals and their Jacobian
  };
  /// True when residuals_and_jacobian() gives Jacobians (e.g. by sensitivities integrated with
  /// the simulation): the solver then asks for one with every point it evaluates instead of
  /// differencing (default: false).
  virtual bool has_jacobian() const { return false; }
  /// The residuals at x and, in the same evaluation, their Jacobian dr/dx (a row per residual, a
  /// column per parameter); the default evaluates residuals() only.
  virtual Evaluated residuals_and_jacobian(const std::vector<double>& x, std::vector<double>& r,
                                           Eigen::MatrixXd& J) const;
};

/// The map between a problem's parameters and the working coordinates u in [0, 1].
class WorkingCoordinates {
public:
  /// The coordinates of a problem's parameters.
  explicit WorkingCoordinates(const std::vector<BoundedParam>& params);
  /// The parameters of u.
  std::vector<double> to_x(const Eigen::VectorXd& u) const;
  /// u of a point, clamped into the box.
  Eigen::VectorXd to_u(const std::vector<double>& x) const;
  /// dx/du of parameter j at x (the box width, or x times the log width).
  double dx_du(std::size_t j, double x) const;

private:
  std::vector<bool> log_;
  std::vector<double> lo_, hi_, origin_, width_; // origin and width of x, or of ln x
};

/// Where the solver starts: a point, and what is already known there.
struct LeastSquaresStart {
  Eigen::VectorXd u;        ///< the start in working coordinates (WorkingCoordinates::to_u)
  std::vector<double> r;    ///< its residuals if known (empty: evaluated first)
  Eigen::MatrixXd jacobian; ///< its Jacobian dr/du if known (empty: computed first)
};

/// When to stop and how to damp.
struct LeastSquaresOptions {
  double ftol = 1e-6; ///< stop when an accepted step lowers the SSE by less than this (relative)
  double xtol = 1e-8; ///< stop when a trial step moves no parameter by this fraction of its box
  int max_iterations = std::numeric_limits<int>::max(); ///< most linearisations (Jacobians)
  /// Most residual evaluations by the solver (finite differences included).
  std::size_t max_evaluations = std::numeric_limits<std::size_t>::max();
  double damping_start = 1e-3; ///< initial damping lambda
  double damping_down = 10.0;  ///< lambda is divided by this after an accepted step...
  double damping_min = 1e-12;  ///< ...down to this
  double damping_up = 10.0;    ///< and multiplied by this after a rejected one
  double damping_max = 1e12;   ///< stop (no descent) when lambda exceeds this
  /// Hold a parameter on a bound whose gradient points outward out of the step (an active set);
  /// otherwise the step is only projected into the box.
  bool hold_at_bounds = true;
  /// Rejected steps in one iteration before stopping (no descent) whatever lambda.
  int max_rejections = std::numeric_limits<int>::max();
  /// Recompute the Jacobian at the final point when the last one was taken before the last step
  /// (what the covariance needs), even beyond max_evaluations.
  bool final_jacobian = true;
  /// Between Jacobians of the problem (or finite differences), update the Jacobian along each
  /// accepted step by Broyden's rank-one secant formula instead of computing a new one; a step of
  /// an updated Jacobian that is rejected makes a new one (and final_jacobian one at the end).
  bool secant_updates = false;
  int threads = 1;                           ///< Jacobian columns in parallel (0: all cores)
  const std::atomic<bool>* cancel = nullptr; ///< set to stop early with the best point so far
};

/// Why the solver stopped.
enum class LeastSquaresStop {
  converged,       ///< relative SSE decrease below ftol
  small_step,      ///< trial step below xtol
  no_descent,      ///< damping beyond damping_max, or max_rejections
  iterations,      ///< max_iterations reached
  budget,          ///< max_evaluations reached
  at_bounds,       ///< every parameter held at a bound by its gradient
  jacobian_failed, ///< a Jacobian column failed on both sides
  cancelled,       ///< the cancel flag was set
  start_failed     ///< the start point could not be evaluated
};

/// The outcome of a solve.
struct LeastSquaresResult {
  bool ok = false;             ///< the start was evaluated: x, r and sse hold the best point
  std::vector<double> x;       ///< the best point
  Eigen::VectorXd u;           ///< x in working coordinates (0 or 1: on a bound)
  std::vector<double> r;       ///< its residuals
  double sse = 0.0;            ///< their sum of squares
  Eigen::MatrixXd jacobian;    ///< the last Jacobian dr/du (empty if none was computed)
  bool jacobian_at_x = false;  ///< that Jacobian was taken at x (not updated along a step)
  int iterations = 0;          ///< linearisations
  std::size_t evaluations = 0; ///< residual evaluations
  std::size_t differenced = 0; ///< Jacobians made by finite differences (not the problem's own)
  std::size_t secant = 0;      ///< Jacobians updated along a step (secant_updates)
  std::size_t accepted = 0;    ///< accepted steps
  LeastSquaresStop stop = LeastSquaresStop::start_failed; ///< why it stopped
};

/// Minimises the sum of squared residuals within the box by Levenberg-Marquardt: Marquardt-scaled
/// damping, the problem's own Jacobian where it gives one (has_jacobian(): evaluated with every
/// trial point, so an accepted step brings the next iteration's Jacobian) and otherwise a
/// forward-difference Jacobian (a backward one at the upper bound, the other side when one
/// fails), bounds kept by projection with a parameter on a bound whose gradient points outward
/// held for the step (hold_at_bounds). Deterministic whatever `threads`.
LeastSquaresResult solve_least_squares(const ResidualProblem& problem, LeastSquaresStart start,
                                       const LeastSquaresOptions& options = {});

/// The stop reason in words (the tolerances as set in `options`).
std::string describe(LeastSquaresStop stop, const LeastSquaresOptions& options);

/// The linearised covariance of a least-squares estimate.
struct LeastSquaresCovariance {
  bool computed = false;                        ///< more residuals than parameters
  std::vector<double> std_errors;               ///< per parameter (inf: no effect on the residuals)
  std::vector<std::vector<double>> correlation; ///< cov_jk / sqrt(cov_jj cov_kk)
  double condition = 1.0;                       ///< condition number of JᵀJ (columns normalised)
  std::vector<std::size_t> no_effect;           ///< parameters whose Jacobian column is zero
  /// True when every parameter is determined: no zero column, and JᵀJ invertible in double
  /// precision (condition below 1 / machine epsilon).
  bool determined() const;
};

/// sigma² (JᵀJ)⁻¹ with sigma² = SSE / (n - p), from the Jacobian dr/du at x, mapped to the
/// parameters. Computed from an SVD of the column-normalised Jacobian with singular values
/// clipped at 1e-12 of the largest, so a combination the data cannot determine shows as a huge
/// standard error and a correlation of ±1 instead of a failure.
LeastSquaresCovariance least_squares_covariance(const ResidualProblem& problem,
                                                const std::vector<double>& x,
                                                const Eigen::MatrixXd& jacobian, double sse);

/// The sum of squares of r, summed in order.
double sum_of_squares(const std::vector<double>& r);

} // namespace thermnet
