#pragma once
/// The prediction-error criterion (CTSM-R, pySIP): a model's cases as continuous-discrete
/// stochastic state-space models (kernel/core/network_state_space.hpp) with process noise on
/// every node and measurement noise on every measured node, filtered by the shared Kalman filter;
/// the one-step-ahead predictions, their innovations and the log-likelihood of the data, and its
/// maximum over the structural params (ranged params, a diagnosis candidate's own) and the noise
/// intensities.

#include "kernel/calibration/calibration_problem.hpp"
#include "kernel/calibration/least_squares.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace thermnet {

/// How the state-space form is set up.
struct PredictionSettings {
  /// Standard deviation of every initial state around the model's start (P0 = sd^2 I), K.
  double initial_sd = 1.0;
  /// Mean propagation between samples (tight: the likelihood's finite differences need it).
  SolverOptions solver = {1e-12, 1e-12};
  int threads = 0; ///< cases and gradient components in parallel (0: all cores)
  /// A nonlinear network without events linearised at the filtered mean for each step (local
  /// linearisation, as CTSM-R does) instead of integrated from it: much faster, slightly
  /// different likelihoods (diagnosis's structure search uses it; calibrate does not).
  bool local_linearisation = false;
  int max_iterations = 200; ///< most quasi-Newton iterations of a fit (each stage)
  double ftol = 1e-9;       ///< a fit stops when an iteration gains less than ftol (1 + |lnL|)
};

/// A parameter of the criterion: a structural one or a noise intensity.
struct PredictionParam {
  std::string name;   ///< ranged param name, candidate parameter, `sigma_w[NODE]`, `sigma_v[NODE]`
  BoundedParam box;   ///< bounds and scale (log for positive ranges)
  double start = 0.0; ///< starting value (SI)
  bool noise = false; ///< a noise intensity (K/sqrt(s) for sigma_w, K for sigma_v)
};

/// Makes a case's network at the structural values x (one per structural param, in order).
using SpecMaker =
    std::function<lang::NetworkSpec(std::size_t case_index, const std::vector<double>& x)>;

/// The one-step-ahead predictions of one case.
struct CaseInnovations {
  std::string case_name;                      ///< the case
  std::vector<double> times;                  ///< measured times, s
  std::vector<std::string> nodes;             ///< filtered measured nodes
  std::vector<std::vector<double>> measured;  ///< per node, per time, K (NaN: missing)
  std::vector<std::vector<double>> predicted; ///< one-step-ahead prediction, K (NaN: missing)
  std::vector<std::vector<double>> sd;        ///< its standard deviation sqrt(S_ii), K
  double log_likelihood = 0.0;                ///< of this case's measurements
  std::size_t points = 0;                     ///< measurements filtered
};

/// The log-likelihood of a model's data as a function of structural params and noise intensities.
class PredictionProblem {
public:
  /// Structural params with the case networks they make, and the cases' data. The noise params
  /// follow the structural ones: sigma_w[NODE] for every node with capacity of the first case's
  /// network at the structural start, then sigma_v[NODE] for every measured unknown node. Throws
  /// std::invalid_argument on a network the filter cannot take (an arithmetic node) or data that
  /// measures no unknown node.
  PredictionProblem(std::vector<PredictionParam> structural, SpecMaker make,
                    std::vector<std::string> cases, std::vector<MeasuredData> data,
                    PredictionSettings settings = {});
  /// A model's ranged params and cases with data (as `calibrate` sees them).
  PredictionProblem(const lang::Model& model, const CalibrationProblem& problem,
                    PredictionSettings settings = {});

  /// Every parameter: structural first, then noise.
  const std::vector<PredictionParam>& params() const { return params_; }
  /// Their boxes (for the optimisers).
  std::vector<BoundedParam> boxes() const;
  /// Their starting values.
  std::vector<double> start() const;
  /// Number of structural params.
  std::size_t structural() const { return structural_; }
  /// The cases.
  const std::vector<std::string>& cases() const { return cases_; }
  /// Measurements filtered (the likelihood's sample size).
  std::size_t points() const;
  /// The settings.
  const PredictionSettings& settings() const { return settings_; }

  /// The log-likelihood at theta; -inf when a case cannot be filtered. Thread-safe.
  double log_likelihood(const std::vector<double>& theta) const;
  /// The one-step-ahead predictions of every case at theta; throws on failure.
  std::vector<CaseInnovations> innovations(const std::vector<double>& theta) const;

  /// What filtering a case needs that depends on the structural params only (defined in the
  /// source file).
  struct CaseSetup;

private:
  struct SetupCache;
  static std::shared_ptr<SetupCache> make_cache();
  /// One case filtered at theta: its likelihood, and with `series` its predictions and spreads.
  CaseInnovations filter_case(std::size_t c, const std::vector<double>& theta, bool series) const;
  std::shared_ptr<CaseSetup> setup(std::size_t c, const std::vector<double>& x) const;
  void add_noise_params();

  std::vector<PredictionParam> params_;
  std::size_t structural_ = 0;
  SpecMaker make_;
  std::vector<std::string> cases_;
  std::vector<MeasuredData> data_;
  PredictionSettings settings_;
  std::vector<std::string> process_nodes_, measured_nodes_;
  // The setups of affine cases at the structural values last met, shared by the evaluations
  // of a gradient that move the noise params only (and by the threads).
  std::shared_ptr<SetupCache> cache_;
};

/// The maximum-likelihood estimate.
struct PredictionFit {
  bool ok = false;                ///< the start could be evaluated
  std::vector<double> theta;      ///< every parameter (structural, then noise)
  double log_likelihood = 0.0;    ///< at theta
  std::size_t parameters = 0;     ///< fitted parameters (the likelihood-ratio tests' count)
  std::size_t points = 0;         ///< measurements
  double aic = 0.0;               ///< -2 lnL + 2 k
  double bic = 0.0;               ///< -2 lnL + k ln n
  std::vector<double> std_errors; ///< from the inverse Hessian (NaN: not determined)
  std::vector<std::vector<double>> correlation; ///< of the parameters (empty when not determined)
  int iterations = 0;                           ///< quasi-Newton iterations
  std::size_t evaluations = 0;    ///< likelihood evaluations (filter runs of every case)
  bool converged = false;         ///< the optimiser met its tolerance
  std::vector<std::string> notes; ///< remarks (params on bounds, a singular Hessian)
};

/// Maximises the log-likelihood over every parameter from `start` (empty: problem.start());
/// with `std_errors`, adds the standard errors from the Hessian. With `deterministic_stage`, the
/// structural params and the measurement noise are first fitted with (almost) no process noise
/// (a start far from the optimum); without it, everything is fitted from `start` at once (a warm
/// start from a fitted model, as the diagnosis refits candidates).
PredictionFit fit_prediction(const PredictionProblem& problem, std::vector<double> start = {},
                             bool std_errors = true, bool deterministic_stage = true);

/// Sets fit.std_errors and fit.correlation from the likelihood's Hessian at fit.theta (2 n^2 + 1
/// evaluations), with a note where it is not positive definite.
void add_standard_errors(const PredictionProblem& problem, PredictionFit& fit);

/// The likelihood-ratio test of a model against a nested smaller one.
struct LikelihoodRatio {
  double statistic = 0.0; ///< 2 (lnL_large - lnL_small)
  int df = 0;             ///< added parameters
  double p_value = 1.0;   ///< P(chi2(df) >= statistic)
};

/// The test of `large` (k_large params) against `small` (k_small < k_large).
LikelihoodRatio likelihood_ratio(double ll_small, std::size_t k_small, double ll_large,
                                 std::size_t k_large);

/// P(chi2(df) >= x), the upper tail of the chi-square distribution.
double chi_square_upper(double x, int df);

} // namespace thermnet
