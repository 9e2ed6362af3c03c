// Series statistics of the diagnosis's evidence: the noise of a measured series and its local
// quadratic smoothing (value and slope).

#include "kernel/diagnosis/diagnosis.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermnet {

double estimate_noise(const std::vector<double>& v) {
  std::vector<double> d;
  for (std::size_t k = 1; k + 1 < v.size(); ++k) {
    const double x = v[k + 1] - 2.0 * v[k] + v[k - 1];
    if (std::isfinite(x)) d.push_back(x);
  }
  if (d.size() < 5) return 0.0;
  auto median = [](std::vector<double> x) {
    std::nth_element(x.begin(), x.begin() + static_cast<long>(x.size() / 2), x.end());
    return x[x.size() / 2];
  };
  const double m = median(d);
  for (double& x : d)
    x = std::abs(x - m);
  const double sigma = 1.4826 * median(d) / std::sqrt(6.0);
  // Quantised readings (a sensor's resolution, an average of such sensors) move by whole steps:
  // their second differences are mostly 0, whatever the rounding error of q^2 / 12 each reading
  // carries. The resolution is the smallest gap between distinct values.
  std::vector<double> u;
  for (double x : v)
    if (std::isfinite(x)) u.push_back(x);
  std::sort(u.begin(), u.end());
  double q = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < u.size(); ++k)
    if (u[k] > u[k - 1]) q = std::min(q, u[k] - u[k - 1]);
  return std::isfinite(q) ? std::sqrt(sigma * sigma + q * q / 12.0) : sigma;
}

void smooth_series(const std::vector<double>& t, const std::vector<double>& v, int half,
                   std::vector<double>& smoothed, std::vector<double>& slope) {
  const std::size_t n = v.size();
  smoothed.assign(n, std::numeric_limits<double>::quiet_NaN());
  slope.assign(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a =
        k >= static_cast<std::size_t>(half) ? k - static_cast<std::size_t>(half) : 0;
    const std::size_t b = std::min(n - 1, k + static_cast<std::size_t>(half));
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    int used = 0;
    const double scale = std::max(1e-9, (t[b] - t[a]) / 2.0);
    for (std::size_t j = a; j <= b; ++j) {
      if (!std::isfinite(v[j])) continue;
      const double x = (t[j] - t[k]) / scale;
      const Eigen::Vector3d phi(1.0, x, x * x);
      A += phi * phi.transpose();
      y += phi * v[j];
      ++used;
    }
    if (used < 4) continue;
    const Eigen::Vector3d c = A.ldlt().solve(y);
    smoothed[k] = c[0];
    slope[k] = c[1] / scale;
  }
}

} // namespace thermnet
