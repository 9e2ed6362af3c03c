// minimise_bounded(): BFGS in logit coordinates of the parameters' boxes; scaled_hessian(): the
// curvature at an optimum for standard errors.

#include "kernel/calibration/quasi_newton.hpp"

#include "kernel/core/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermnet {
namespace {

constexpr double kEdge = 1e-9; // u kept within [kEdge, 1 - kEdge]
// Central differences from the first iteration that lowers f by less than this share of 1 + |f|.
constexpr double kNearDrop = 1e-4;

double logit(double u) {
  u = std::clamp(u, kEdge, 1.0 - kEdge);
  return std::log(u / (1.0 - u));
}

double logistic(double z) {
  return z >= 0 ? 1.0 / (1.0 + std::exp(-z)) : std::exp(z) / (1.0 + std::exp(z));
}

class Transformed {
public:
  Transformed(const ScalarObjective& f, const std::vector<BoundedParam>& params)
      : f_(f), coords_(params), n_(params.size()) {}

  std::vector<double> x_of(const Eigen::VectorXd& z) const {
    Eigen::VectorXd u(z.size());
    for (Eigen::Index j = 0; j < z.size(); ++j)
      u(j) = logistic(z(j));
    return coords_.to_x(u);
  }
  Eigen::VectorXd z_of(const std::vector<double>& x) const {
    const Eigen::VectorXd u = coords_.to_u(x);
    Eigen::VectorXd z(u.size());
    for (Eigen::Index j = 0; j < u.size(); ++j)
      z(j) = logit(u(j));
    return z;
  }
  double value(const Eigen::VectorXd& z) const {
    const double v = f_(x_of(z));
    return std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
  }
  // Central differences (one-sided where a side fails), or forward differences (n evaluations
  // instead of 2n; backward where the forward side fails); false when no side can be evaluated.
  bool gradient(const Eigen::VectorXd& z, double fz, double h, bool central, int threads,
                Eigen::VectorXd& g, std::size_t& evaluations) const {
    std::vector<double> plus(n_), minus(n_, std::numeric_limits<double>::infinity());
    const std::size_t sides = central ? 2 : 1;
    parallel_for(sides * n_, threads, [&](std::size_t k) {
      Eigen::VectorXd zz = z;
      const std::size_t j = k / sides;
      const bool up = k % sides == 0;
      zz(static_cast<Eigen::Index>(j)) += (up ? h : -h);
      (up ? plus : minus)[j] = value(zz);
    });
    evaluations += sides * n_;
    g.resize(static_cast<Eigen::Index>(n_));
    for (std::size_t j = 0; j < n_; ++j) {
      if (!central && !std::isfinite(plus[j])) {
        Eigen::VectorXd zz = z;
        zz(static_cast<Eigen::Index>(j)) -= h;
        minus[j] = value(zz);
        ++evaluations;
      }
      const bool p = std::isfinite(plus[j]), m = std::isfinite(minus[j]);
      const auto i = static_cast<Eigen::Index>(j);
      if (p && m)
        g(i) = (plus[j] - minus[j]) / (2 * h);
      else if (p)
        g(i) = (plus[j] - fz) / h;
      else if (m)
        g(i) = (fz - minus[j]) / h;
      else
        return false;
    }
    return true;
  }

private:
  const ScalarObjective& f_;
  WorkingCoordinates coords_;
  std::size_t n_;
};

} // namespace

QuasiNewtonResult minimise_bounded(const ScalarObjective& f,
                                   const std::vector<BoundedParam>& params,
                                   const std::vector<double>& start, const QuasiNewtonOptions& o) {
  QuasiNewtonResult res;
  const Transformed t(f, params);
  Eigen::VectorXd z = t.z_of(start);
  double fz = t.value(z);
  ++res.evaluations;
  res.x = t.x_of(z);
  res.f = fz;
  if (!std::isfinite(fz)) return res;
  res.ok = true;
  const auto n = z.size();
  if (n == 0) {
    res.converged = true;
    return res;
  }
  // Forward differences while far from the minimum, where the gradient is large beside their
  // error (half the step times the curvature); central ones from where the drops become small,
  // and before any stop is decided (a small gradient, a failed line search).
  bool central = false;
  Eigen::VectorXd g;
  if (!t.gradient(z, fz, o.step, central, o.threads, g, res.evaluations)) return res;
  const auto sharpen = [&] {
    central = true;
    return t.gradient(z, fz, o.step, central, o.threads, g, res.evaluations);
  };
  Eigen::MatrixXd Hinv = Eigen::MatrixXd::Identity(n, n);
  bool scaled = false;
  for (res.iterations = 0; res.iterations < o.max_iterations; ++res.iterations) {
    if (g.cwiseAbs().maxCoeff() < o.gtol && !central && !sharpen()) break;
    if (g.cwiseAbs().maxCoeff() < o.gtol) {
      res.converged = true;
      break;
    }
    Eigen::VectorXd d = -Hinv * g;
    if (!(g.dot(d) < 0.0)) { // not a descent direction: restart from steepest descent
      Hinv.setIdentity();
      scaled = false;
      d = -g;
    }
    // Keep a step within a few units of z (the logistic saturates beyond): trust the model there.
    const double longest = d.cwiseAbs().maxCoeff();
    if (longest > 4.0) d *= 4.0 / longest;
    double a = 1.0, fa = 0.0;
    Eigen::VectorXd za;
    bool accepted = false;
    for (int k = 0; k < 30; ++k, a *= 0.5) {
      za = z + a * d;
      fa = t.value(za);
      ++res.evaluations;
      if (std::isfinite(fa) && fa <= fz + 1e-4 * a * g.dot(d)) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      if (!central) { // the forward gradient may be what failed: retry with a central one
        if (!sharpen()) break;
        continue;
      }
      if (scaled || Hinv != Eigen::MatrixXd::Identity(n, n)) { // retry along the gradient
        Hinv.setIdentity();
        scaled = false;
        continue;
      }
      res.converged = true; // no descent along the gradient: a (numerical) minimum
      break;
    }
    Eigen::VectorXd ga;
    if (!t.gradient(za, fa, o.step, central, o.threads, ga, res.evaluations)) break;
    const Eigen::VectorXd s = za - z, y = ga - g;
    const double drop = fz - fa;
    z = za;
    fz = fa;
    g = ga;
    const double sy = s.dot(y);
    if (sy > 1e-12 * s.norm() * y.norm()) {
      if (!scaled) { // Shanno's scaling of the first inverse Hessian
        Hinv *= sy / y.squaredNorm();
        scaled = true;
      }
      const double rho = 1.0 / sy;
      const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
      Hinv = (I - rho * s * y.transpose()) * Hinv * (I - rho * y * s.transpose()) +
             rho * s * s.transpose();
    }
    if (!central && drop < kNearDrop * (1.0 + std::abs(fz))) {
      if (!sharpen()) break;
      continue; // (an ftol stop is decided on a central gradient's next iteration)
    }
    if (drop < o.ftol * (1.0 + std::abs(fz))) {
      res.converged = true;
      ++res.iterations;
      break;
    }
  }
  res.x = t.x_of(z);
  res.f = fz;
  return res;
}

Eigen::MatrixXd scaled_hessian(const ScalarObjective& f, const std::vector<BoundedParam>& params,
                               const std::vector<double>& x, double step, int threads) {
  const std::size_t n = params.size();
  std::vector<double> y(n), h(n);
  for (std::size_t j = 0; j < n; ++j) {
    const bool lg = params[j].scale == ParamScale::log;
    y[j] = lg ? std::log(x[j]) : x[j];
    const double width =
        lg ? std::log(params[j].hi) - std::log(params[j].lo) : params[j].hi - params[j].lo;
    h[j] = step * (width > 0 ? width : 1.0);
  }
  auto at = [&](const std::vector<double>& yy) {
    std::vector<double> xx(n);
    for (std::size_t j = 0; j < n; ++j)
      xx[j] = params[j].scale == ParamScale::log ? std::exp(yy[j]) : yy[j];
    const double v = f(xx);
    return std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN();
  };
  // f(y +- h_i e_i +- h_j e_j) for i <= j: four points per pair (two on the diagonal, plus f(y)).
  const double f0 = at(y);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i; j < n; ++j)
      pairs.emplace_back(i, j);
  std::vector<double> H(pairs.size());
  parallel_for(pairs.size(), threads, [&](std::size_t k) {
    const auto [i, j] = pairs[k];
    auto shifted = [&](double si, double sj) {
      std::vector<double> yy = y;
      yy[i] += si * h[i];
      yy[j] += sj * h[j];
      return at(yy);
    };
    if (i == j)
      H[k] = (shifted(1, 0) - 2 * f0 + shifted(-1, 0)) / (h[i] * h[i]);
    else
      H[k] =
          (shifted(1, 1) - shifted(1, -1) - shifted(-1, 1) + shifted(-1, -1)) / (4 * h[i] * h[j]);
  });
  Eigen::MatrixXd out(n, n);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [i, j] = pairs[k];
    out(i, j) = out(j, i) = H[k];
  }
  return out;
}

} // namespace thermnet
