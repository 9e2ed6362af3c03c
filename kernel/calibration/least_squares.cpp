// The bounded least-squares core: working coordinates, the projected Levenberg-Marquardt loop, the
// finite-difference Jacobian and the covariance of the estimate.

#include "kernel/calibration/least_squares.hpp"

#include "kernel/core/parallel.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

double ResidualProblem::difference_step(std::size_t, const std::vector<double>&) const {
  return 1e-3;
}

ResidualProblem::Evaluated ResidualProblem::residuals_and_jacobian(const std::vector<double>& x,
                                                                   std::vector<double>& r,
                                                                   Eigen::MatrixXd&) const {
  return residuals(x, r) ? Evaluated::residuals : Evaluated::nothing;
}

double sum_of_squares(const std::vector<double>& r) {
  double s = 0.0;
  for (double v : r)
    s += v * v;
  return s;
}

// ------------------------------------------------------------------ working coordinates

WorkingCoordinates::WorkingCoordinates(const std::vector<BoundedParam>& params) {
  for (const auto& p : params) {
    const bool log = p.scale == ParamScale::log;
    log_.push_back(log);
    lo_.push_back(p.lo);
    hi_.push_back(p.hi);
    origin_.push_back(log ? std::log(p.lo) : p.lo);
    width_.push_back(log ? std::log(p.hi) - std::log(p.lo) : p.hi - p.lo);
  }
}

std::vector<double> WorkingCoordinates::to_x(const VectorXd& u) const {
  std::vector<double> x(lo_.size());
  for (std::size_t j = 0; j < x.size(); ++j) {
    const double v = origin_[j] + width_[j] * u[static_cast<Index>(j)];
    // exp may round past a bound; the linear map is exact at u = 0 and stays within an ulp at 1
    x[j] = log_[j] ? std::clamp(std::exp(v), lo_[j], hi_[j]) : v;
  }
  return x;
}

VectorXd WorkingCoordinates::to_u(const std::vector<double>& x) const {
  VectorXd u(static_cast<Index>(x.size()));
  for (std::size_t j = 0; j < x.size(); ++j) {
    const double v = log_[j] ? std::log(std::clamp(x[j], lo_[j], hi_[j])) : x[j];
    u[static_cast<Index>(j)] =
        width_[j] > 0 ? std::clamp((v - origin_[j]) / width_[j], 0.0, 1.0) : 0.0;
  }
  return u;
}

double WorkingCoordinates::dx_du(std::size_t j, double x) const {
  return log_[j] ? x * width_[j] : width_[j];
}

// ------------------------------------------------------------------ the solver

namespace {

/// Forward differences, one column per parameter (in parallel: each writes its own column),
/// backward at the upper bound and the other side when one fails (its column then stays zero and
/// `complete` false).
MatrixXd forward_differences(const ResidualProblem& problem, const WorkingCoordinates& coords,
                             const VectorXd& u, const std::vector<double>& r, int threads,
                             const std::atomic<bool>* cancel, std::atomic<std::size_t>& evaluations,
                             bool& complete) {
  const auto n = static_cast<Index>(r.size());
  const std::size_t p = problem.params().size();
  MatrixXd J = MatrixXd::Zero(n, static_cast<Index>(p));
  const std::vector<double> x = coords.to_x(u);
  std::vector<char> ok(p, 0);
  parallel_for(
      p, threads,
      [&](std::size_t j) {
        const auto jj = static_cast<Index>(j);
        const double step = problem.difference_step(j, x);
        double h = u[jj] + step <= 1.0 ? step : -step;
        for (int attempt = 0; attempt < 2 && !ok[j]; ++attempt, h = -h) {
          VectorXd v = u;
          v[jj] += h;
          if (v[jj] < 0.0 || v[jj] > 1.0) continue;
          std::vector<double> rv;
          const bool good = problem.residuals(coords.to_x(v), rv);
          ++evaluations;
          if (!good || static_cast<Index>(rv.size()) != n || !std::isfinite(sum_of_squares(rv)))
            continue;
          for (Index i = 0; i < n; ++i)
            J(i, jj) = (rv[static_cast<std::size_t>(i)] - r[static_cast<std::size_t>(i)]) / h;
          ok[j] = 1;
        }
      },
      cancel);
  complete = std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
  return J;
}

/// One solve: the problem in working coordinates, with its evaluation count.
class Solver {
public:
  Solver(const ResidualProblem& problem, const LeastSquaresOptions& options)
      : problem_(problem), options_(options), coords_(problem.params()),
        p_(problem.params().size()), analytic_(problem.has_jacobian()) {}

  LeastSquaresResult run(LeastSquaresStart start);

private:
  /// What one damped step (with its retries) decided: accepted, stop, or a rejected step of an
  /// updated Jacobian (a new one is needed).
  enum class Step { accepted, stop, refresh };

  bool cancelled() const { return options_.cancel && options_.cancel->load(); }
  bool evaluate(const VectorXd& u, std::vector<double>& r, double& sse,
                MatrixXd* J = nullptr) const;
  bool jacobian(const VectorXd& u, const std::vector<double>& r, MatrixXd& J);
  Step step(const MatrixXd& J, double& lambda, bool updated);

  const ResidualProblem& problem_;
  const LeastSquaresOptions& options_;
  WorkingCoordinates coords_;
  std::size_t p_;
  bool analytic_; // the problem gives Jacobians
  mutable std::atomic<std::size_t> evaluations_{0};
  std::size_t differenced_ = 0, secant_ = 0;
  MatrixXd next_J_; // the problem's Jacobian at the last accepted trial (empty: none)
  // the current point
  VectorXd u_;
  std::vector<double> r_;
  double sse_ = 0.0;
  std::size_t accepted_ = 0;
  LeastSquaresStop stop_ = LeastSquaresStop::budget;
};

/// The residuals at u and, with J and a problem that gives Jacobians, dr/du there (J is left
/// empty when the problem could not give it).
bool Solver::evaluate(const VectorXd& u, std::vector<double>& r, double& sse, MatrixXd* J) const {
  const std::vector<double> x = coords_.to_x(u);
  bool ok = false;
  if (J && analytic_) {
    MatrixXd Jx;
    const auto what = problem_.residuals_and_jacobian(x, r, Jx);
    ok = what != ResidualProblem::Evaluated::nothing;
    J->resize(0, 0);
    if (what == ResidualProblem::Evaluated::both && Jx.rows() == static_cast<Index>(r.size()) &&
        Jx.cols() == static_cast<Index>(p_) && Jx.allFinite()) {
      for (std::size_t j = 0; j < p_; ++j)
        Jx.col(static_cast<Index>(j)) *= coords_.dx_du(j, x[j]);
      *J = std::move(Jx);
    }
  } else {
    ok = problem_.residuals(x, r);
  }
  ++evaluations_;
  sse = ok ? sum_of_squares(r) : 0.0;
  return ok && std::isfinite(sse);
}

/// The problem's Jacobian at u when it gives one; otherwise forward differences, one column per
/// parameter (in parallel: each writes its own column), backward at the upper bound and the
/// other side when one fails.
bool Solver::jacobian(const VectorXd& u, const std::vector<double>& r, MatrixXd& J) {
  if (analytic_) {
    std::vector<double> again;
    double sse = 0.0;
    if (evaluate(u, again, sse, &J) && J.size() > 0) return true;
  }
  ++differenced_;
  bool complete = false;
  J = forward_differences(problem_, coords_, u, r, options_.threads, options_.cancel, evaluations_,
                          complete);
  return complete;
}

/// The damped Gauss-Newton step on the free parameters (a parameter on a bound whose gradient
/// points outward is held), raising the damping until a step lowers the SSE; with an `updated`
/// (secant) Jacobian, the first rejection asks for a new Jacobian instead.
Solver::Step Solver::step(const MatrixXd& J, double& lambda, bool updated) {
  const VectorXd rv = Eigen::Map<const VectorXd>(r_.data(), static_cast<Index>(r_.size()));
  const VectorXd g = J.transpose() * rv;
  const MatrixXd A = J.transpose() * J;
  std::vector<Index> free;
  for (Index j = 0; j < static_cast<Index>(p_); ++j)
    if (!options_.hold_at_bounds || !((u_[j] <= 0.0 && g[j] > 0) || (u_[j] >= 1.0 && g[j] < 0)))
      free.push_back(j);
  if (free.empty()) {
    stop_ = LeastSquaresStop::at_bounds;
    return Step::stop;
  }
  const auto nf = static_cast<Index>(free.size());
  MatrixXd Af(nf, nf);
  VectorXd gf(nf);
  for (Index a = 0; a < nf; ++a) {
    gf[a] = g[free[static_cast<std::size_t>(a)]];
    for (Index b = 0; b < nf; ++b)
      Af(a, b) = A(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]);
  }
  const double dmax = Af.diagonal().maxCoeff();
  for (int rejected = 0;;) {
    if (cancelled()) {
      stop_ = LeastSquaresStop::cancelled;
      return Step::stop;
    }
    if (evaluations_.load() >= options_.max_evaluations) {
      stop_ = LeastSquaresStop::budget;
      return Step::stop;
    }
    MatrixXd M = Af;
    for (Index a = 0; a < nf; ++a)
      M(a, a) += lambda * std::max(Af(a, a), 1e-12 * dmax);
    const VectorXd df = M.ldlt().solve(-gf);
    VectorXd trial = u_;
    for (Index a = 0; a < nf; ++a) {
      const Index j = free[static_cast<std::size_t>(a)];
      trial[j] = std::clamp(u_[j] + df[a], 0.0, 1.0);
    }
    const double moved = (trial - u_).lpNorm<Eigen::Infinity>();
    if (!(moved >= options_.xtol)) {
      stop_ = LeastSquaresStop::small_step;
      return Step::stop;
    }
    std::vector<double> r;
    double sse = 0.0;
    MatrixXd J_trial;
    const bool with_jacobian = analytic_ && !options_.secant_updates;
    if (evaluate(trial, r, sse, with_jacobian ? &J_trial : nullptr) && sse < sse_) {
      const double rel = (sse_ - sse) / std::max(sse_, 1e-300);
      u_ = trial;
      r_ = std::move(r);
      sse_ = sse;
      next_J_ = std::move(J_trial);
      ++accepted_;
      lambda = std::max(lambda / options_.damping_down, options_.damping_min);
      if (rel < options_.ftol) {
        stop_ = LeastSquaresStop::converged;
        return Step::stop;
      }
      return Step::accepted;
    }
    if (updated) return Step::refresh;
    lambda *= options_.damping_up;
    if (lambda > options_.damping_max || ++rejected >= options_.max_rejections) {
      stop_ = LeastSquaresStop::no_descent;
      return Step::stop;
    }
  }
}

LeastSquaresResult Solver::run(LeastSquaresStart start) {
  LeastSquaresResult out;
  u_ = std::move(start.u);
  MatrixXd J = std::move(start.jacobian);
  const bool start_jacobian = J.size() > 0;
  if (start.r.empty()) {
    if (!evaluate(u_, r_, sse_, analytic_ && !start_jacobian ? &J : nullptr)) {
      out.evaluations = evaluations_.load();
      return out; // stop: start_failed
    }
  } else {
    r_ = std::move(start.r);
    sse_ = sum_of_squares(r_);
  }
  bool given = J.rows() == static_cast<Index>(r_.size()) && J.cols() == static_cast<Index>(p_);
  bool current = false; // J was taken at u_
  bool updated = false; // J was updated along steps since it was taken
  double lambda = options_.damping_start;
  VectorXd u_before;
  std::vector<double> r_before;
  for (;;) {
    if (cancelled()) {
      stop_ = LeastSquaresStop::cancelled;
      break;
    }
    if (out.iterations >= options_.max_iterations) {
      stop_ = LeastSquaresStop::iterations;
      break;
    }
    if (!given) {
      if (evaluations_.load() + (analytic_ ? 1 : p_) + 1 > options_.max_evaluations) {
        stop_ = LeastSquaresStop::budget;
        break;
      }
      if (!jacobian(u_, r_, J)) {
        current = false;
        stop_ = LeastSquaresStop::jacobian_failed;
        break;
      }
      updated = false;
    }
    given = false;
    current = !updated;
    ++out.iterations;
    const std::size_t before = accepted_;
    next_J_.resize(0, 0);
    if (options_.secant_updates) {
      u_before = u_;
      r_before = r_;
    }
    const Step s = step(J, lambda, updated);
    const bool moved = accepted_ != before;
    if (s == Step::refresh) { // a new Jacobian here, and the step again
      --out.iterations;
      continue;
    }
    if (moved && next_J_.size() > 0) { // the trial's own Jacobian: the next linearisation
      J = std::move(next_J_);
      given = current = true;
      updated = false;
    } else if (moved && options_.secant_updates) { // Broyden: J du = dr along the step
      const VectorXd du = u_ - u_before;
      const double norm2 = du.squaredNorm();
      if (norm2 > 0.0) {
        VectorXd dr(static_cast<Index>(r_.size()));
        for (std::size_t i = 0; i < r_.size(); ++i)
          dr[static_cast<Index>(i)] = r_[i] - r_before[i];
        J += (dr - J * du) * (du.transpose() / norm2);
        ++secant_;
      }
      given = true;
      current = false;
      updated = true;
    } else {
      current = current && !moved;
    }
    if (s == Step::stop) break;
  }
  if (options_.final_jacobian && !current && !cancelled()) current = jacobian(u_, r_, J);
  out.ok = true;
  out.x = coords_.to_x(u_);
  out.u = u_;
  out.r = std::move(r_);
  out.sse = sse_;
  out.jacobian = std::move(J);
  out.jacobian_at_x = current;
  out.evaluations = evaluations_.load();
  out.differenced = differenced_;
  out.secant = secant_;
  out.accepted = accepted_;
  out.stop = stop_;
  return out;
}

/// A tolerance as short text: 1e-06 -> 1e-6, 1e+12 -> 1e12.
std::string short_number(double v) {
  std::string s = fmt::format("{:g}", v);
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  std::string exponent = s.substr(e + 1);
  const bool negative = exponent[0] == '-';
  exponent.erase(0, exponent.find_first_not_of("+-0"));
  return s.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}

} // namespace

LeastSquaresResult solve_least_squares(const ResidualProblem& problem, LeastSquaresStart start,
                                       const LeastSquaresOptions& options) {
  Solver solver(problem, options);
  return solver.run(std::move(start));
}

std::string describe(LeastSquaresStop stop, const LeastSquaresOptions& o) {
  switch (stop) {
  case LeastSquaresStop::converged:
    return "relative SSE decrease below " + short_number(o.ftol);
  case LeastSquaresStop::small_step:
    return "step below " + short_number(o.xtol) + " of the ranges";
  case LeastSquaresStop::no_descent:
    return "no descent direction (damping above " + short_number(o.damping_max) + ")";
  case LeastSquaresStop::iterations:
    return fmt::format("{} iterations", o.max_iterations);
  case LeastSquaresStop::budget:
    return "budget exhausted";
  case LeastSquaresStop::at_bounds:
    return "every param is held at a bound";
  case LeastSquaresStop::jacobian_failed:
    return "a finite-difference evaluation failed on both sides";
  case LeastSquaresStop::cancelled:
    return "cancelled";
  case LeastSquaresStop::start_failed:
    return "the start could not be evaluated";
  }
  return {};
}

// ------------------------------------------------------------------ covariance

bool LeastSquaresCovariance::determined() const {
  return computed && no_effect.empty() && condition < 1.0 / std::numeric_limits<double>::epsilon();
}

LeastSquaresCovariance least_squares_covariance(const ResidualProblem& problem,
                                                const std::vector<double>& x, const MatrixXd& Ju,
                                                double sse) {
  const WorkingCoordinates coords(problem.params());
  const Index n = Ju.rows(), p = Ju.cols();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  LeastSquaresCovariance cov;
  cov.std_errors.assign(static_cast<std::size_t>(p), nan);
  cov.correlation.assign(static_cast<std::size_t>(p),
                         std::vector<double>(static_cast<std::size_t>(p), nan));
  if (n <= p) return cov;
  cov.computed = true;
  const double sigma2 = sse / static_cast<double>(n - p);
  // Columns normalised to unit length (zero columns left out), so the SVD sees the shape of the
  // problem and not the units.
  const VectorXd c = Ju.colwise().norm().transpose();
  std::vector<Index> live;
  for (Index j = 0; j < p; ++j)
    if (c[j] > 0) live.push_back(j);
  if (live.empty()) { // no parameter has an effect: nothing to decompose (an SVD of n x 0 crashes)
    for (Index j = 0; j < p; ++j) {
      cov.std_errors[static_cast<std::size_t>(j)] = std::numeric_limits<double>::infinity();
      cov.no_effect.push_back(static_cast<std::size_t>(j));
    }
    return cov;
  }
  MatrixXd Js(n, static_cast<Index>(live.size()));
  for (std::size_t k = 0; k < live.size(); ++k)
    Js.col(static_cast<Index>(k)) = Ju.col(live[k]) / c[live[k]];
  Eigen::JacobiSVD<MatrixXd> svd(Js, Eigen::ComputeThinV);
  VectorXd s = svd.singularValues();
  if (s.size() > 0) {
    const double floor = 1e-12 * s[0];
    cov.condition = s[0] * s[0] / std::max(s[s.size() - 1] * s[s.size() - 1], floor * floor);
    for (Index k = 0; k < s.size(); ++k)
      s[k] = 1.0 / std::pow(std::max(s[k], floor), 2);
  }
  const MatrixXd& V = svd.matrixV();
  const MatrixXd cov_s = V * s.asDiagonal() * V.transpose();
  for (std::size_t a = 0; a < live.size(); ++a) {
    const auto ja = static_cast<std::size_t>(live[a]);
    const double va = cov_s(static_cast<Index>(a), static_cast<Index>(a));
    cov.std_errors[ja] = std::sqrt(sigma2 * va) / c[live[a]] * coords.dx_du(ja, x[ja]);
    for (std::size_t b = 0; b < live.size(); ++b) {
      const double vb = cov_s(static_cast<Index>(b), static_cast<Index>(b));
      cov.correlation[ja][static_cast<std::size_t>(live[b])] =
          cov_s(static_cast<Index>(a), static_cast<Index>(b)) / std::sqrt(va * vb);
    }
  }
  for (Index j = 0; j < p; ++j)
    if (c[j] == 0) {
      cov.std_errors[static_cast<std::size_t>(j)] = std::numeric_limits<double>::infinity();
      cov.no_effect.push_back(static_cast<std::size_t>(j));
    }
  return cov;
}

} // namespace thermnet
