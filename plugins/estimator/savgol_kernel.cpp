// Savitzky-Golay FIR kernels (see savgol_kernel.hpp).
//
// The fit over j = 0..W-1 (s = (j - h) / h) has coefficients a = G^-1 M with M_m = sum_j s_j^m y_j,
// so a_k = sum_j w_k[j] y_j with w_k[j] = sum_m G^-1(k, m) s_j^m: one dot product per coefficient.

#include "plugins/estimator/savgol_kernel.hpp"

#include <algorithm>
#include <stdexcept>

namespace thermnet::estimation {

Eigen::MatrixXd savgol_gram_inverse(int half, int order) {
  const int p = order;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(p + 1, p + 1);
  Eigen::VectorXd powers(2 * p + 1);
  for (int j = -half; j <= half; ++j) {
    double s = static_cast<double>(j) / half, pw = 1.0;
    for (int k = 0; k <= 2 * p; ++k, pw *= s)
      powers(k) = pw;
    for (int a = 0; a <= p; ++a)
      for (int b = 0; b <= p; ++b)
        G(a, b) += powers(a + b);
  }
  return G.ldlt().solve(Eigen::MatrixXd::Identity(p + 1, p + 1));
}

SavgolKernel::SavgolKernel(int window, int order)
    : window_(window), half_((window - 1) / 2), order_(order) {
  if (window < 3 || window % 2 == 0 || order < 0 || order >= window || order > 12)
    throw std::invalid_argument("a Savitzky-Golay kernel needs an odd window >= 3 and an order "
                                "in 0..min(window - 1, 12)");
  const Eigen::MatrixXd Ginv = savgol_gram_inverse(half_, order_);
  const auto W = static_cast<std::size_t>(window_);
  poly_.assign(static_cast<std::size_t>(order_ + 1) * W, 0.0);
  end_value_.assign(W, 0.0);
  end_slope_.assign(W, 0.0);
  std::vector<double> powers(static_cast<std::size_t>(order_ + 1));
  for (std::size_t j = 0; j < W; ++j) {
    double s = (static_cast<double>(j) - half_) / half_, pw = 1.0;
    for (int m = 0; m <= order_; ++m, pw *= s)
      powers[static_cast<std::size_t>(m)] = pw;
    for (int k = 0; k <= order_; ++k) {
      double w = 0.0;
      for (int m = 0; m <= order_; ++m)
        w += Ginv(k, m) * powers[static_cast<std::size_t>(m)];
      poly_[static_cast<std::size_t>(k) * W + j] = w;
      end_value_[j] += w;
      end_slope_[j] += k * w / half_;
    }
  }
}

namespace {
double dot(const std::vector<double>& w, std::size_t offset, const double* y, int n) {
  return Eigen::Map<const Eigen::VectorXd>(w.data() + offset, n)
      .dot(Eigen::Map<const Eigen::VectorXd>(y, n));
}
} // namespace

std::pair<double, double> SavgolKernel::centre(const double* y) const {
  const auto W = static_cast<std::size_t>(window_);
  double value = dot(poly_, 0, y, window_);
  double slope = order_ > 0 ? dot(poly_, W, y, window_) / half_ : 0.0;
  return {value, slope};
}

std::pair<double, double> SavgolKernel::newest(const double* y) const {
  return {dot(end_value_, 0, y, window_), dot(end_slope_, 0, y, window_)};
}

void SavgolKernel::evaluate(const double* y, int from, int to, double* value, double* slope) const {
  double a[13];
  const auto W = static_cast<std::size_t>(window_);
  for (int k = 0; k <= order_; ++k)
    a[k] = dot(poly_, static_cast<std::size_t>(k) * W, y, window_);
  for (int j = from; j < to; ++j) {
    double s = static_cast<double>(j - half_) / half_, v = 0.0, dv = 0.0, pw = 1.0;
    for (int k = 0; k <= order_; ++k, pw *= s) {
      v += a[k] * pw;
      if (k < order_) dv += (k + 1) * a[k + 1] * pw;
    }
    value[j - from] = v;
    slope[j - from] = dv / half_;
  }
}

void savgol_window(const SavgolKernel& kernel, const double* y, const double* centred_value,
                   const double* centred_slope, std::size_t n, double dt, double* value,
                   double* slope) {
  const auto W = static_cast<std::size_t>(kernel.window());
  const auto h = static_cast<std::size_t>(kernel.half());
  if (n < W) throw std::invalid_argument("savgol_window: fewer samples than the kernel's window");
  kernel.evaluate(y, 0, kernel.half(), value, slope);
  std::copy(centred_value + h, centred_value + (n - h), value + h);
  std::copy(centred_slope + h, centred_slope + (n - h), slope + h);
  kernel.evaluate(y + (n - W), kernel.half() + 1, kernel.window(), value + (n - h),
                  slope + (n - h));
  for (std::size_t i = 0; i < n; ++i)
    slope[i] /= dt;
}

} // namespace thermnet::estimation
