// Optimizer plugin 'lm': Levenberg-Marquardt least squares from the model's current values, by the
// bounded least-squares core (kernel/calibration/least_squares.hpp) on the calibration problem.
//
// Coordinates. Every param is linear in its range, u = (x - lo) / (hi - lo) in [0, 1]: every param
// then has the same order of magnitude whatever its unit. Bounds are kept by projection: a trial
// point is clamped into the box, and a param sitting on a bound whose gradient pushes it outward
// is frozen for that step (a simple active set). Unlike a logit transform this can reach an
// optimum on the bound and keeps the Jacobian from vanishing near it.
//
// Jacobian. Forward differences with a step of 1e-3 of the range (backward at the upper bound,
// the other side if one side fails), one column per param, columns in parallel with
// parallel_for (each writes its own column: the result does not depend on the thread count).
// Every evaluation of the run, the base points included, uses solver tolerances tightened to
// rtol = atol = 1e-9 so the integration noise (~1e-9 x 300 K) stays far below the effect of the
// step (1e-3 of a range typically moves temperatures by 1e-3..1e-2 K).
//
// Stopping. A relative SSE decrease below 1e-6 on an accepted step, a step below 1e-8 of the
// ranges, a damping beyond 1e12 (no descent), or the budget (`samples` = most evaluations,
// default 30 (p + 1), FD evaluations included; the p evaluations of the final Jacobian for the
// statistics are made even when the budget is spent, and counted).
//
// Statistics. At the final point the Jacobian is recomputed (counted) and the covariance of the
// params is sigma^2 (J^T J)^-1 in SI with sigma^2 = SSE / (n - p) (least_squares_covariance: a
// combination the data cannot determine shows as a huge standard error and a correlation of +-1).

#include "kernel/calibration/least_squares.hpp"
#include "kernel/calibration/optimizer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

namespace thermnet {
namespace {

constexpr double kFdTolerance = 1e-9; // solver rtol/atol for every evaluation of the run

/// The calibration problem as a residual problem, with counting and progress.
class CalibrationResiduals final : public ResidualProblem {
public:
  CalibrationResiduals(const CalibrationProblem& problem, const OptimizerSettings& s)
      : problem_(problem), settings_(s) {
    const std::vector<double> lo = problem.lower(), hi = problem.upper();
    for (std::size_t j = 0; j < lo.size(); ++j)
      params_.push_back({lo[j], hi[j], ParamScale::linear});
    options_.keep_residuals = true;
    options_.solver = s.solver;
    options_.solver.rtol = std::min(s.solver.rtol, kFdTolerance);
    options_.solver.atol = std::min(s.solver.atol, kFdTolerance);
    budget_ = s.samples > 0 ? s.samples : 30 * (lo.size() + 1);
  }

  const std::vector<BoundedParam>& params() const override { return params_; }
  bool residuals(const std::vector<double>& x, std::vector<double>& r) const override {
    Evaluation e = evaluate(x);
    r = std::move(e.residuals);
    return e.ok;
  }

  std::size_t evaluations() const { return evaluations_.load(); }
  std::size_t budget() const { return budget_; }

  /// Evaluates x (counted; reports progress). A result with the wrong residual count is not ok.
  Evaluation evaluate(const std::vector<double>& x) const {
    Evaluation e = problem_.evaluate(x, options_);
    if (e.ok && e.residuals.size() != e.points) e.ok = false;
    std::size_t done = ++evaluations_;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (e.ok && (std::isnan(best_rmse_) || e.rmse < best_rmse_)) best_rmse_ = e.rmse;
      if (settings_.on_progress) settings_.on_progress(Progress{done, budget_, best_rmse_});
    }
    return e;
  }

private:
  const CalibrationProblem& problem_;
  const OptimizerSettings& settings_;
  std::vector<BoundedParam> params_;
  EvaluationOptions options_;
  std::size_t budget_ = 0;
  mutable std::atomic<std::size_t> evaluations_{0};
  mutable std::mutex mutex_;
  mutable double best_rmse_ = std::numeric_limits<double>::quiet_NaN();
};

/// Standard errors (SI), correlation matrix and their notes at the final point.
void add_statistics(const CalibrationResiduals& problem, const LeastSquaresResult& fit,
                    const std::vector<lang::ParamInfo>& params, OptimizerResult& r) {
  const LeastSquaresCovariance cov =
      least_squares_covariance(problem, fit.x, fit.jacobian, fit.sse);
  r.std_errors = cov.std_errors;
  r.correlation = cov.correlation;
  if (!cov.computed) {
    r.notes.push_back("lm: no standard errors: not more points than params");
    return;
  }
  if (cov.condition > 1e12)
    r.notes.push_back(fmt::format(
        "lm: J^T J is nearly singular (condition {:.3g}): some combination of params is "
        "not identifiable from the data (see the correlation matrix)",
        cov.condition));
  for (std::size_t j : cov.no_effect)
    r.notes.push_back(fmt::format("lm: param '{}' has no effect on the residuals (the data do not "
                                  "depend on it at the fit: its value is not an estimate)",
                                  params.at(j).name));
}

class LevenbergMarquardt final : public Optimizer {
public:
  OptimizerResult run(const CalibrationProblem& problem, const OptimizerSettings& s) override;
};

OptimizerResult LevenbergMarquardt::run(const CalibrationProblem& problem,
                                        const OptimizerSettings& s) {
  const auto t0 = std::chrono::steady_clock::now();
  OptimizerResult r;
  r.method = "lm";
  const CalibrationResiduals residuals(problem, s);
  const WorkingCoordinates coords(residuals.params());
  auto finish = [&](OptimizerResult& out) {
    out.evaluations = out.samples = residuals.evaluations();
    out.simulations = out.evaluations * problem.cases().size();
    out.cancelled = s.cancel && s.cancel->load();
    out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  };

  LeastSquaresStart start;
  start.u = coords.to_u(s.start.empty() ? problem.initial() : s.start);
  Evaluation cur = residuals.evaluate(coords.to_x(start.u));
  if (!cur.ok) {
    r.notes.push_back("lm: the start point failed (" + cur.failure + "); starting at mid-range");
    start.u = Eigen::VectorXd::Constant(start.u.size(), 0.5);
    cur = residuals.evaluate(coords.to_x(start.u));
  }
  if (!cur.ok) {
    r.notes.push_back("lm: no evaluable start point: " + cur.failure);
    return finish(r);
  }
  start.r = std::move(cur.residuals);

  LeastSquaresOptions options;
  options.max_evaluations =
      residuals.budget() - std::min(residuals.budget(), residuals.evaluations());
  options.threads = s.threads;
  options.cancel = s.cancel;
  const LeastSquaresResult fit = solve_least_squares(residuals, std::move(start), options);

  r.found = true;
  r.best = fit.x;
  r.rmse = cur.points > 0 ? std::sqrt(fit.sse / static_cast<double>(cur.points)) : 0.0;
  r.r2 = problem.r_squared(fit.sse);
  r.accepted = 1 + fit.accepted; // the start and every accepted step
  if (fit.jacobian_at_x)
    add_statistics(residuals, fit, problem.params(), r);
  else
    r.notes.push_back("lm: no Jacobian at the final point: no standard errors");
  for (Eigen::Index j = 0; j < fit.u.size(); ++j)
    if (fit.u[j] <= 0.0 || fit.u[j] >= 1.0)
      r.notes.push_back(fmt::format("lm: param '{}' ends on a bound of its range (its standard "
                                    "error assumes it is free)",
                                    problem.params()[static_cast<std::size_t>(j)].name));
  r.notes.insert(r.notes.begin(),
                 fmt::format("lm: {} iterations, RMSE {:.4g} -> {:.4g} K, stopped: {}; finite "
                             "differences of 1e-3 of each range with solver rtol = atol = {:g}",
                             fit.iterations, cur.rmse, r.rmse, describe(fit.stop, options),
                             std::min(s.solver.rtol, kFdTolerance)));
  return finish(r);
}

OptimizerPlugin make_lm() {
  return {.name = "lm",
          .doc = "Levenberg-Marquardt least squares from the declared values (or a given start), "
                 "bounded by "
                 "the ranges; standard errors and correlations",
          .create = [] { return std::make_unique<LevenbergMarquardt>(); },
          .budget = "most evaluations (30 (p + 1)), finite-difference evaluations included"};
}

} // namespace
THERMNET_REGISTER(OptimizerPlugin, make_lm);
} // namespace thermnet
