#pragma once
/// Savitzky-Golay weights of one (window, order), computed once and applied as dot products, for a
/// sliding window over a stream: each sample's centred value and slope is computed once, as soon
/// as the sample half a window ahead arrives, and a window's filtered arrays then only need the
/// end fits of its first and last half-window (savgol_window).

#include <Eigen/Dense>

#include <cstddef>
#include <utility>
#include <vector>

namespace thermnet::estimation {

/// Inverse Gram matrix of the powers s^0..s^order over s = j/h, j = -h..h (the normal equations
/// of a Savitzky-Golay fit in the scaled abscissa s).
Eigen::MatrixXd savgol_gram_inverse(int half, int order);

/// FIR kernels of a Savitzky-Golay fit over `window` samples (odd, > order, >= 3).
class SavgolKernel {
public:
  SavgolKernel() = default;
  /// Builds the kernels; throws std::invalid_argument for an even window, window < 3 or order
  /// outside 0..min(window - 1, 12).
  SavgolKernel(int window, int order);
  /// Samples covered (odd).
  int window() const { return window_; }
  /// Half-width h = (window - 1) / 2.
  int half() const { return half_; }
  /// Value and slope (per sample) of the fit to y[0, window) at its centre y[h].
  std::pair<double, double> centre(const double* y) const;
  /// Value and slope (per sample) of the fit to y[0, window) at its last sample (SciPy 'interp').
  std::pair<double, double> newest(const double* y) const;
  /// Values and slopes (per sample) of the fit to y[0, window) at its samples from..to-1.
  void evaluate(const double* y, int from, int to, double* value, double* slope) const;

private:
  int window_ = 0, half_ = 0, order_ = 0;
  std::vector<double> poly_;      // row k (window entries): weights of the coefficient of s^k
  std::vector<double> end_value_; // weights of the value at s = 1
  std::vector<double> end_slope_; // weights of the slope (per sample) at s = 1
};

/// Savitzky-Golay values and slopes (per second) over y[0, n), n >= window, equal to
/// savitzky_golay(): the inside samples are copied from `centred_value` / `centred_slope` (the
/// kernel's centre() of each sample, per sample, aligned with y), the first and last half-window
/// come from the end fits.
void savgol_window(const SavgolKernel& kernel, const double* y, const double* centred_value,
                   const double* centred_slope, std::size_t n, double dt, double* value,
                   double* slope);

} // namespace thermnet::estimation
