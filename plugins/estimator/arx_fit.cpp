#include "plugins/estimator/arx_fit.hpp"

#include <cmath>

namespace thermnet::estimation {

ArxCoefficients fit_arx(const double* upper, const double* middle, const double* d_middle,
                        const double* lower, std::size_t n) {
  ArxCoefficients c;
  if (n < 2) return c;
  // One pass over the window: the 2x2 normal equations of the regressors x1 = d_middle and
  // x2 = middle - lower against y = upper - middle. No allocation, O(n).
  double s11 = 0.0, s12 = 0.0, s22 = 0.0, s1y = 0.0, s2y = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x1 = d_middle[i], x2 = middle[i] - lower[i], y = upper[i] - middle[i];
    s11 += x1 * x1;
    s12 += x1 * x2;
    s22 += x2 * x2;
    s1y += x1 * y;
    s2y += x2 * y;
  }
  // Scaled to unit column norms, so the rank decision does not depend on units (s vs K): the
  // Gram matrix is [[1, r], [r, 1]], singular when the regressors are (nearly) collinear.
  const double n1 = std::sqrt(s11), n2 = std::sqrt(s22);
  if (!(n1 > 0.0) || !(n2 > 0.0) || !std::isfinite(n1) || !std::isfinite(n2)) return c;
  const double r = s12 / (n1 * n2), det = 1.0 - r * r;
  constexpr double collinear = 1e-10; // below this, the normal equations keep < 6 digits
  if (!(det > collinear)) return c;
  const double b1 = s1y / n1, b2 = s2y / n2;
  c.tau = (b1 - r * b2) / det / n1;
  c.xi = (b2 - r * b1) / det / n2;
  c.ok = std::isfinite(c.tau) && std::isfinite(c.xi);
  return c;
}

} // namespace thermnet::estimation
