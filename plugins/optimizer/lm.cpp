// Optimizer plugin 'lm': Levenberg-Marquardt least squares from the model's current values.
//
// Coordinates. LM works in scaled coordinates u = (x - lo) / (hi - lo) in [0, 1]: every param
// then has the same order of magnitude whatever its unit. Bounds are kept by projection: a
// trial point is clamped into the box, and a param sitting on a bound whose gradient pushes it
// outward is frozen for that step (a simple active set). Unlike a logit transform this can
// reach an optimum on the bound and keeps the Jacobian from vanishing near it.
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
// params is sigma^2 (J^T J)^-1 in SI with sigma^2 = SSE / (n - p). It is computed from an SVD
// of the column-normalised Jacobian with singular values clipped at 1e-12 of the largest, so a
// combination the data cannot determine shows as a huge standard error and a correlation of
// +-1 (its direction dominates the covariance) instead of a failure.

#include "kernel/calibration/optimizer.hpp"
#include "kernel/core/parallel.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

namespace thermnet {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kFdStep = 1e-3;      // forward-difference step, fraction of the range
constexpr double kFdTolerance = 1e-9; // solver rtol/atol for every evaluation of the run
constexpr double kFtol = 1e-6;        // relative SSE decrease that counts as converged
constexpr double kXtol = 1e-8;        // step (fraction of the ranges) that counts as converged
constexpr double kLambdaMax = 1e12;   // damping beyond which no descent is possible

/// One LM run: the problem in scaled coordinates, with counting and progress.
class LmRun {
public:
  LmRun(const CalibrationProblem& problem, const OptimizerSettings& s)
      : problem_(problem), settings_(s), lo_(problem.lower()), width_(problem.upper()) {
    for (std::size_t j = 0; j < lo_.size(); ++j)
      width_[j] -= lo_[j];
    options_.keep_residuals = true;
    options_.solver = s.solver;
    options_.solver.rtol = std::min(s.solver.rtol, kFdTolerance);
    options_.solver.atol = std::min(s.solver.atol, kFdTolerance);
    const std::size_t p = lo_.size();
    budget_ = s.samples > 0 ? s.samples : 30 * (p + 1);
  }

  std::size_t dimension() const { return lo_.size(); }
  std::size_t evaluations() const { return evaluations_.load(); }
  std::size_t budget() const { return budget_; }
  bool cancelled() const { return settings_.cancel && settings_.cancel->load(); }
  const std::vector<double>& width() const { return width_; }

  /// The SI point of u.
  std::vector<double> to_x(const VectorXd& u) const {
    std::vector<double> x(lo_.size());
    for (std::size_t j = 0; j < x.size(); ++j)
      x[j] = lo_[j] + width_[j] * u[static_cast<Eigen::Index>(j)];
    return x;
  }

  /// u of an SI point, clamped into the box.
  VectorXd to_u(const std::vector<double>& x) const {
    VectorXd u(static_cast<Eigen::Index>(x.size()));
    for (std::size_t j = 0; j < x.size(); ++j)
      u[static_cast<Eigen::Index>(j)] =
          width_[j] > 0 ? std::clamp((x[j] - lo_[j]) / width_[j], 0.0, 1.0) : 0.0;
    return u;
  }

  /// Evaluates u (counted; reports progress). A result with the wrong residual count is not ok.
  Evaluation evaluate(const VectorXd& u) {
    Evaluation e = problem_.evaluate(to_x(u), options_);
    if (e.ok && e.residuals.size() != e.points) e.ok = false;
    std::size_t done = ++evaluations_;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (e.ok && (std::isnan(best_rmse_) || e.rmse < best_rmse_)) best_rmse_ = e.rmse;
      if (settings_.on_progress) settings_.on_progress(Progress{done, budget_, best_rmse_});
    }
    return e;
  }

  /// Forward-difference Jacobian (residuals x params) at u, columns in parallel; false if a
  /// column could not be computed on either side.
  bool jacobian(const VectorXd& u, const Evaluation& base, MatrixXd& J) {
    const std::size_t p = dimension();
    const auto n = static_cast<Eigen::Index>(base.residuals.size());
    J.setZero(n, static_cast<Eigen::Index>(p));
    std::vector<char> ok(p, 0);
    parallel_for(
        p, settings_.threads,
        [&](std::size_t j) {
          const auto jj = static_cast<Eigen::Index>(j);
          double h = u[jj] + kFdStep <= 1.0 ? kFdStep : -kFdStep;
          for (int attempt = 0; attempt < 2 && !ok[j]; ++attempt, h = -h) {
            VectorXd v = u;
            v[jj] += h;
            if (v[jj] < 0.0 || v[jj] > 1.0) continue;
            Evaluation e = evaluate(v);
            if (!e.ok || static_cast<Eigen::Index>(e.residuals.size()) != n) continue;
            for (Eigen::Index i = 0; i < n; ++i)
              J(i, jj) = (e.residuals[static_cast<std::size_t>(i)] -
                          base.residuals[static_cast<std::size_t>(i)]) /
                         h;
            ok[j] = 1;
          }
        },
        settings_.cancel);
    return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
  }

private:
  const CalibrationProblem& problem_;
  const OptimizerSettings& settings_;
  std::vector<double> lo_, width_;
  EvaluationOptions options_;
  std::size_t budget_ = 0;
  std::atomic<std::size_t> evaluations_{0};
  std::mutex mutex_;
  double best_rmse_ = std::numeric_limits<double>::quiet_NaN();
};

VectorXd residual_vector(const Evaluation& e) {
  return Eigen::Map<const VectorXd>(e.residuals.data(),
                                    static_cast<Eigen::Index>(e.residuals.size()));
}

/// Standard errors (SI) and correlation matrix from the Jacobian in u, as in the file header.
void covariance(const MatrixXd& Ju, const std::vector<double>& width, double sse,
                OptimizerResult& r) {
  const Eigen::Index n = Ju.rows(), p = Ju.cols();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.std_errors.assign(static_cast<std::size_t>(p), nan);
  r.correlation.assign(static_cast<std::size_t>(p),
                       std::vector<double>(static_cast<std::size_t>(p), nan));
  if (n <= p) {
    r.notes.push_back("lm: no standard errors: not more points than params");
    return;
  }
  const double sigma2 = sse / static_cast<double>(n - p);
  VectorXd c = Ju.colwise().norm().transpose();
  std::vector<Eigen::Index> live;
  for (Eigen::Index j = 0; j < p; ++j)
    if (c[j] > 0) live.push_back(j);
  MatrixXd Js(n, static_cast<Eigen::Index>(live.size()));
  for (std::size_t k = 0; k < live.size(); ++k)
    Js.col(static_cast<Eigen::Index>(k)) = Ju.col(live[k]) / c[live[k]];
  Eigen::JacobiSVD<MatrixXd> svd(Js, Eigen::ComputeThinV);
  VectorXd s = svd.singularValues();
  if (s.size() > 0) {
    const double floor = 1e-12 * s[0];
    if (s[s.size() - 1] < 1e-6 * s[0])
      r.notes.push_back(fmt::format(
          "lm: J^T J is nearly singular (condition {:.3g}): some combination of params is "
          "not identifiable from the data (see the correlation matrix)",
          s[0] * s[0] / std::max(s[s.size() - 1] * s[s.size() - 1], floor * floor)));
    for (Eigen::Index k = 0; k < s.size(); ++k)
      s[k] = 1.0 / std::pow(std::max(s[k], floor), 2);
  }
  const MatrixXd& V = svd.matrixV();
  MatrixXd cov_s = V * s.asDiagonal() * V.transpose();
  for (std::size_t a = 0; a < live.size(); ++a) {
    const auto ja = static_cast<std::size_t>(live[a]);
    const double va = cov_s(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(a));
    r.std_errors[ja] = std::sqrt(sigma2 * va) / c[live[a]] * width[ja];
    for (std::size_t b = 0; b < live.size(); ++b) {
      const double vb = cov_s(static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(b));
      r.correlation[ja][static_cast<std::size_t>(live[b])] =
          cov_s(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) / std::sqrt(va * vb);
    }
  }
  for (Eigen::Index j = 0; j < p; ++j)
    if (c[j] == 0) {
      r.std_errors[static_cast<std::size_t>(j)] = std::numeric_limits<double>::infinity();
      r.notes.push_back(fmt::format("lm: param #{} has no effect on the residuals", j + 1));
    }
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
  LmRun run(problem, s);
  const std::size_t p = run.dimension();
  const auto pe = static_cast<Eigen::Index>(p);
  auto finish = [&](OptimizerResult& out) {
    out.evaluations = out.samples = run.evaluations();
    out.simulations = out.evaluations * problem.cases().size();
    out.cancelled = run.cancelled();
    out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  };

  VectorXd u = run.to_u(s.start.empty() ? problem.initial() : s.start);
  Evaluation cur = run.evaluate(u);
  if (!cur.ok) {
    r.notes.push_back("lm: the start point failed (" + cur.failure + "); starting at mid-range");
    u = VectorXd::Constant(pe, 0.5);
    cur = run.evaluate(u);
  }
  if (!cur.ok) {
    r.notes.push_back("lm: no evaluable start point: " + cur.failure);
    return finish(r);
  }
  std::size_t accepted_points = 1; // the start and every accepted step
  const double start_rmse = cur.rmse;

  double lambda = 1e-3;
  int iterations = 0;
  std::string reason = "budget exhausted";
  MatrixXd J;
  bool jac_current = false;
  bool done = false;
  while (!done) {
    if (run.cancelled()) {
      reason = "cancelled";
      break;
    }
    if (run.evaluations() + p + 1 > run.budget()) break;
    if (!run.jacobian(u, cur, J)) {
      reason = "a finite-difference evaluation failed on both sides";
      break;
    }
    jac_current = true;
    ++iterations;
    const VectorXd rv = residual_vector(cur);
    const VectorXd g = J.transpose() * rv;
    const MatrixXd A = J.transpose() * J;
    std::vector<Eigen::Index> free;
    for (Eigen::Index j = 0; j < pe; ++j)
      if (!((u[j] <= 0.0 && g[j] > 0) || (u[j] >= 1.0 && g[j] < 0))) free.push_back(j);
    if (free.empty()) {
      reason = "every param is held at a bound";
      break;
    }
    const auto nf = static_cast<Eigen::Index>(free.size());
    MatrixXd Af(nf, nf);
    VectorXd gf(nf);
    for (Eigen::Index a = 0; a < nf; ++a) {
      gf[a] = g[free[static_cast<std::size_t>(a)]];
      for (Eigen::Index b = 0; b < nf; ++b)
        Af(a, b) = A(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]);
    }
    const double dmax = Af.diagonal().maxCoeff();
    while (true) {
      if (run.cancelled()) {
        reason = "cancelled";
        done = true;
        break;
      }
      if (run.evaluations() >= run.budget()) {
        done = true;
        break;
      }
      MatrixXd M = Af;
      for (Eigen::Index a = 0; a < nf; ++a)
        M(a, a) += lambda * std::max(Af(a, a), 1e-12 * dmax);
      const VectorXd df = M.ldlt().solve(-gf);
      VectorXd trial = u;
      for (Eigen::Index a = 0; a < nf; ++a) {
        const Eigen::Index j = free[static_cast<std::size_t>(a)];
        trial[j] = std::clamp(u[j] + df[a], 0.0, 1.0);
      }
      const double step = (trial - u).lpNorm<Eigen::Infinity>();
      if (!(step >= kXtol)) {
        reason = "step below 1e-8 of the ranges";
        done = true;
        break;
      }
      Evaluation e = run.evaluate(trial);
      if (e.ok && e.sse < cur.sse) {
        const double rel = (cur.sse - e.sse) / cur.sse;
        u = trial;
        cur = std::move(e);
        jac_current = false;
        ++accepted_points;
        lambda = std::max(lambda / 10.0, 1e-12);
        if (rel < kFtol) {
          reason = "relative SSE decrease below 1e-6";
          done = true;
        }
        break;
      }
      lambda *= 10.0;
      if (lambda > kLambdaMax) {
        reason = "no descent direction (damping above 1e12)";
        done = true;
        break;
      }
    }
  }

  r.found = true;
  r.best = run.to_x(u);
  r.rmse = cur.rmse;
  r.r2 = cur.r2;
  r.accepted = accepted_points;
  if (!jac_current && !run.cancelled()) jac_current = run.jacobian(u, cur, J);
  if (jac_current)
    covariance(J, run.width(), cur.sse, r);
  else
    r.notes.push_back("lm: no Jacobian at the final point: no standard errors");
  for (Eigen::Index j = 0; j < pe; ++j)
    if (u[j] <= 0.0 || u[j] >= 1.0)
      r.notes.push_back(fmt::format("lm: param '{}' ends on a bound of its range (its standard "
                                    "error assumes it is free)",
                                    problem.params()[static_cast<std::size_t>(j)].name));
  r.notes.insert(r.notes.begin(),
                 fmt::format("lm: {} iterations, RMSE {:.4g} -> {:.4g} K, stopped: {}; finite "
                             "differences of 1e-3 of each range with solver rtol = atol = {:g}",
                             iterations, start_rmse, cur.rmse, reason,
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
