// Unit tests of the bounded least-squares core (kernel/calibration/least_squares.hpp) on problems
// with known answers: a straight-line fit with its analytic covariance, the same fit with a bound
// active, Rosenbrock's valley, a log-scaled time constant, warm starts, budgets and threads.

#include "kernel/calibration/least_squares.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <vector>

namespace {

using namespace thermnet;

/// A residual problem from a function.
class FunctionProblem final : public ResidualProblem {
public:
  using Residuals = std::function<std::vector<double>(const std::vector<double>&)>;
  FunctionProblem(std::vector<BoundedParam> params, Residuals f, double step = 1e-3)
      : params_(std::move(params)), f_(std::move(f)), step_(step) {}
  const std::vector<BoundedParam>& params() const override { return params_; }
  bool residuals(const std::vector<double>& x, std::vector<double>& r) const override {
    r = f_(x);
    return true;
  }
  double difference_step(std::size_t, const std::vector<double>&) const override { return step_; }

private:
  std::vector<BoundedParam> params_;
  Residuals f_;
  double step_;
};

/// Data of a straight line y = 1.5 + 0.25 t with a fixed, deterministic scatter.
struct Line {
  std::vector<double> t, y;
  Line() {
    for (int i = 0; i < 20; ++i) {
      t.push_back(i);
      y.push_back(1.5 + 0.25 * i + 0.3 * std::sin(1.7 * i * i + 0.4));
    }
  }
  /// Residuals of a + b t.
  std::vector<double> operator()(const std::vector<double>& x) const {
    std::vector<double> r;
    for (std::size_t i = 0; i < t.size(); ++i)
      r.push_back(x[0] + x[1] * t[i] - y[i]);
    return r;
  }
  /// The design matrix [1 t].
  Eigen::MatrixXd design() const {
    Eigen::MatrixXd X(static_cast<Eigen::Index>(t.size()), 2);
    for (std::size_t i = 0; i < t.size(); ++i)
      X.row(static_cast<Eigen::Index>(i)) << 1.0, t[i];
    return X;
  }
  Eigen::VectorXd values() const {
    return Eigen::Map<const Eigen::VectorXd>(y.data(), static_cast<Eigen::Index>(y.size()));
  }
};

LeastSquaresStart start_at(const ResidualProblem& p, const std::vector<double>& x) {
  LeastSquaresStart s;
  s.u = WorkingCoordinates(p.params()).to_u(x);
  return s;
}

} // namespace

TEST_CASE("least squares: a straight line gives the normal-equation solution and its covariance") {
  const Line line;
  const FunctionProblem problem({{-100, 100}, {-10, 10}}, line);
  const LeastSquaresResult fit = solve_least_squares(problem, start_at(problem, {0.0, 0.0}));
  REQUIRE(fit.ok);
  const Eigen::MatrixXd X = line.design();
  const Eigen::VectorXd beta = (X.transpose() * X).ldlt().solve(X.transpose() * line.values());
  CHECK(fit.x[0] == doctest::Approx(beta[0]).epsilon(1e-9));
  CHECK(fit.x[1] == doctest::Approx(beta[1]).epsilon(1e-9));
  REQUIRE(fit.jacobian_at_x);

  // sigma² (XᵀX)⁻¹ with sigma² = SSE / (n - p): the textbook covariance of the estimate.
  const double sse = (X * beta - line.values()).squaredNorm();
  const Eigen::MatrixXd cov = (X.transpose() * X).inverse() * (sse / (20.0 - 2.0));
  const LeastSquaresCovariance c = least_squares_covariance(problem, fit.x, fit.jacobian, fit.sse);
  REQUIRE(c.computed);
  CHECK(c.determined());
  CHECK(fit.sse == doctest::Approx(sse).epsilon(1e-12));
  CHECK(c.std_errors[0] == doctest::Approx(std::sqrt(cov(0, 0))).epsilon(1e-7));
  CHECK(c.std_errors[1] == doctest::Approx(std::sqrt(cov(1, 1))).epsilon(1e-7));
  CHECK(c.correlation[0][1] ==
        doctest::Approx(cov(0, 1) / std::sqrt(cov(0, 0) * cov(1, 1))).epsilon(1e-7));
  CHECK(c.correlation[0][0] == doctest::Approx(1.0));
}

TEST_CASE("least squares: an active bound holds its parameter and fits the others given it") {
  const Line line;
  const double b_hi = 0.2; // below the free optimum (about 0.25)
  const FunctionProblem problem({{-100, 100}, {-10, b_hi}}, line);
  const LeastSquaresResult fit = solve_least_squares(problem, start_at(problem, {0.0, 0.0}));
  REQUIRE(fit.ok);
  CHECK(fit.u[1] == 1.0);
  CHECK(fit.x[1] == doctest::Approx(b_hi).epsilon(1e-15));
  // Given b on its bound, the best a is the mean of y - b t.
  double a = 0.0;
  for (std::size_t i = 0; i < line.t.size(); ++i)
    a += (line.y[i] - b_hi * line.t[i]) / static_cast<double>(line.t.size());
  CHECK(fit.x[0] == doctest::Approx(a).epsilon(1e-9));
}

TEST_CASE("least squares: Rosenbrock's valley, the same whatever the threads") {
  const FunctionProblem problem({{-2, 2}, {-2, 2}}, [](const std::vector<double>& x) {
    return std::vector<double>{10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]};
  });
  LeastSquaresOptions o;
  o.ftol = 1e-14;
  o.xtol = 1e-14;
  const LeastSquaresResult fit = solve_least_squares(problem, start_at(problem, {-1.2, 1.0}), o);
  REQUIRE(fit.ok);
  MESSAGE("Rosenbrock: ", fit.iterations, " iterations, ", fit.evaluations, " evaluations, ",
          describe(fit.stop, o));
  CHECK(fit.x[0] == doctest::Approx(1.0).epsilon(1e-6));
  CHECK(fit.x[1] == doctest::Approx(1.0).epsilon(1e-6));
  CHECK(fit.sse < 1e-12);
  o.threads = 3;
  const LeastSquaresResult parallel =
      solve_least_squares(problem, start_at(problem, {-1.2, 1.0}), o);
  CHECK(parallel.x == fit.x);
  CHECK(parallel.evaluations == fit.evaluations);
}

TEST_CASE("least squares: a log-scaled time constant over seven decades") {
  // y = A exp(-t / tau), A = 5, tau = 30; tau searched in [0.01, 1e5] from 3000.
  std::vector<double> t, y;
  for (int i = 0; i <= 60; ++i) {
    t.push_back(2.0 * i);
    y.push_back(5.0 * std::exp(-t.back() / 30.0) + 0.01 * std::sin(2.3 * i * i));
  }
  auto decay = [&](const std::vector<double>& x) {
    std::vector<double> r;
    for (std::size_t i = 0; i < t.size(); ++i)
      r.push_back(x[0] * std::exp(-t[i] / x[1]) - y[i]);
    return r;
  };
  const FunctionProblem wide({{0, 100}, {0.01, 1e5, ParamScale::log}}, decay);
  const LeastSquaresResult fit = solve_least_squares(wide, start_at(wide, {1.0, 3000.0}));
  REQUIRE(fit.ok);
  CHECK(fit.x[0] == doctest::Approx(5.0).epsilon(0.01));
  CHECK(fit.x[1] == doctest::Approx(30.0).epsilon(0.01));

  // The covariance does not depend on the scale a parameter is stepped in (fine differences, so
  // that their truncation error does not show).
  const FunctionProblem log({{0, 100}, {10, 100, ParamScale::log}}, decay, 1e-7);
  const FunctionProblem lin({{0, 100}, {10, 100}}, decay, 1e-7);
  LeastSquaresOptions o;
  o.ftol = 1e-12;
  const LeastSquaresResult a = solve_least_squares(log, start_at(log, {1.0, 50.0}), o);
  const LeastSquaresResult b = solve_least_squares(lin, start_at(lin, {1.0, 50.0}), o);
  REQUIRE(a.jacobian_at_x);
  REQUIRE(b.jacobian_at_x);
  CHECK(a.x[1] == doctest::Approx(b.x[1]).epsilon(1e-6));
  const auto ca = least_squares_covariance(log, a.x, a.jacobian, a.sse);
  const auto cb = least_squares_covariance(lin, b.x, b.jacobian, b.sse);
  MESSAGE("tau = ", a.x[1], " +- ", ca.std_errors[1], " (log scale), ", b.x[1], " +- ",
          cb.std_errors[1], " (linear)");
  CHECK(ca.std_errors[0] == doctest::Approx(cb.std_errors[0]).epsilon(1e-5));
  CHECK(ca.std_errors[1] == doctest::Approx(cb.std_errors[1]).epsilon(1e-5));
}

TEST_CASE("least squares: a warm start needs no first Jacobian; budgets and iterations bound it") {
  const Line line;
  const FunctionProblem problem({{-100, 100}, {-10, 10}}, line);
  const LeastSquaresResult full = solve_least_squares(problem, start_at(problem, {0.0, 0.0}));
  REQUIRE(full.jacobian_at_x);

  LeastSquaresOptions one;
  one.max_iterations = 1;
  one.damping_start = 1e-12; // a Gauss-Newton step: exact for a linear problem
  one.final_jacobian = false;
  LeastSquaresStart warm = start_at(problem, {0.0, 0.0});
  warm.r = line({0.0, 0.0});
  warm.jacobian = full.jacobian; // exact for a linear problem
  const LeastSquaresResult w = solve_least_squares(problem, warm, one);
  CHECK(w.iterations == 1);
  CHECK(w.evaluations == 1); // the trial step only
  CHECK(w.x[1] == doctest::Approx(full.x[1]).epsilon(1e-9));
  CHECK(w.stop == LeastSquaresStop::iterations);

  LeastSquaresOptions budget;
  budget.max_evaluations = 4;
  budget.final_jacobian = false;
  const LeastSquaresResult b = solve_least_squares(problem, start_at(problem, {0.0, 0.0}), budget);
  CHECK(b.evaluations <= 4);
  CHECK(b.stop == LeastSquaresStop::budget);

  // At the exact optimum no step lowers the SSE: the rejection limit stops it.
  const FunctionProblem exact(
      {{0, 1}}, [](const std::vector<double>& x) { return std::vector<double>{x[0] - 0.25}; });
  LeastSquaresOptions three;
  three.xtol = 0.0;
  three.max_rejections = 3;
  three.final_jacobian = false;
  const LeastSquaresResult e = solve_least_squares(exact, start_at(exact, {0.25}), three);
  CHECK(e.stop == LeastSquaresStop::no_descent);
  CHECK(e.evaluations == 1 + 1 + 3); // start, Jacobian, three rejected steps
  CHECK(e.x[0] == 0.25);
}

TEST_CASE("least squares: an undetermined combination and a parameter without effect") {
  // Only a + b is determined; c does nothing.
  const Line line;
  const FunctionProblem problem({{-10, 10}, {-10, 10}, {0, 1}}, [&](const std::vector<double>& x) {
    std::vector<double> r;
    for (std::size_t i = 0; i < line.t.size(); ++i)
      r.push_back(x[0] + x[1] - line.y[i]);
    return r;
  });
  const LeastSquaresResult fit = solve_least_squares(problem, start_at(problem, {1.0, 1.0, 0.5}));
  REQUIRE(fit.jacobian_at_x);
  double mean = 0.0;
  for (double v : line.y)
    mean += v / static_cast<double>(line.y.size());
  CHECK(fit.x[0] + fit.x[1] == doctest::Approx(mean).epsilon(1e-6));
  const auto c = least_squares_covariance(problem, fit.x, fit.jacobian, fit.sse);
  CHECK_FALSE(c.determined());
  CHECK(c.condition > 1e20);
  CHECK(c.correlation[0][1] == doctest::Approx(-1.0).epsilon(1e-6));
  CHECK(c.no_effect == std::vector<std::size_t>{2});
  CHECK(std::isinf(c.std_errors[2]));
}

TEST_CASE("least squares: stop reasons in words") {
  const LeastSquaresOptions o;
  CHECK(describe(LeastSquaresStop::converged, o) == "relative SSE decrease below 1e-6");
  CHECK(describe(LeastSquaresStop::small_step, o) == "step below 1e-8 of the ranges");
  CHECK(describe(LeastSquaresStop::no_descent, o) == "no descent direction (damping above 1e12)");
}
