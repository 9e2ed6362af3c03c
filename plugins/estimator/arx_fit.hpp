#pragma once
/// The TIM-AB heat-transfer relation between three equally spaced points of a slab, and its
/// least-squares fit (Sensors 2025, 25(7), 2227).
///
/// Calibration on the deeper triple B, C, D: T_B = tau dT_C/dt + (xi + 1) T_C - xi T_D.
/// Estimate on the shallower triple A, B, C: T_A = tau dT_B/dt + (xi + 1) T_B - xi T_C.

#include <cstddef>

namespace thermnet::estimation {

/// Fitted coefficients of the relation.
struct ArxCoefficients {
  double tau = 0.0; ///< tau-hat, s (the thermal hysteresis time)
  double xi = 0.0;  ///< xi-hat, dimensionless
  bool ok = false;  ///< false when the regressors are degenerate (constant data)
};

/// Least squares over n samples of `upper = tau d(middle)/dt + (xi + 1) middle - xi lower`, i.e.
/// upper - middle = tau d_middle + xi (middle - lower), solved by the normal equations of the
/// unit-scaled columns in one allocation-free pass; ok is false when the regressors are collinear.
ArxCoefficients fit_arx(const double* upper, const double* middle, const double* d_middle,
                        const double* lower, std::size_t n);

/// The relation applied one step towards the surface: tau d_upper + (xi + 1) upper - xi middle.
inline double arx_extrapolate(const ArxCoefficients& c, double upper, double d_upper,
                              double middle) {
  return c.tau * d_upper + (c.xi + 1.0) * upper - c.xi * middle;
}

} // namespace thermnet::estimation
