#include "plugins/estimator/arx_fit.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace thermnet::estimation {

ArxCoefficients fit_arx(const double* upper, const double* middle, const double* d_middle,
                        const double* lower, std::size_t n) {
  ArxCoefficients c;
  if (n < 2) return c;
  const auto rows = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd X(rows, 2);
  Eigen::VectorXd y(rows);
  for (Eigen::Index i = 0; i < rows; ++i) {
    X(i, 0) = d_middle[i];
    X(i, 1) = middle[i] - lower[i];
    y(i) = upper[i] - middle[i];
  }
  // Scale the columns so the rank decision does not depend on units (s vs K).
  Eigen::Vector2d scale;
  for (int j = 0; j < 2; ++j) {
    scale(j) = X.col(j).norm();
    if (!(scale(j) > 0.0) || !std::isfinite(scale(j))) return c;
    X.col(j) /= scale(j);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  qr.setThreshold(1e-12);
  if (qr.rank() < 2) return c;
  Eigen::Vector2d beta = qr.solve(y);
  c.tau = beta(0) / scale(0);
  c.xi = beta(1) / scale(1);
  c.ok = std::isfinite(c.tau) && std::isfinite(c.xi);
  return c;
}

} // namespace thermnet::estimation
