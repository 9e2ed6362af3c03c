// test_whiteness(): autocorrelation with its white-noise band and the cumulated periodogram with
// its Kolmogorov-Smirnov band (the periodogram by Eigen's FFT).

#include "kernel/calibration/whiteness.hpp"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace thermnet {
namespace {

// Smallest k with P(Binomial(n, p) <= k) >= q.
std::size_t binomial_quantile(std::size_t n, double p, double q) {
  double term = std::pow(1.0 - p, static_cast<double>(n)), cdf = term;
  std::size_t k = 0;
  while (cdf < q && k < n) {
    term *= static_cast<double>(n - k) / static_cast<double>(k + 1) * p / (1.0 - p);
    ++k;
    cdf += term;
  }
  return k;
}

} // namespace

Whiteness test_whiteness(const std::vector<double>& e, double dt, std::size_t max_lag) {
  Whiteness w;
  w.n = e.size();
  w.dt = dt;
  const std::size_t n = e.size();
  if (n < 8) return w;
  double mean = 0.0;
  for (double v : e)
    mean += v;
  mean /= static_cast<double>(n);
  std::vector<double> x(n);
  for (std::size_t k = 0; k < n; ++k)
    x[k] = e[k] - mean;
  // Autocorrelation (the biased estimator, as R's acf).
  if (max_lag == 0) max_lag = std::min<std::size_t>(n / 3, 200);
  max_lag = std::min(max_lag, n - 1);
  double c0 = 0.0;
  for (double v : x)
    c0 += v * v;
  w.acf.assign(max_lag + 1, 0.0);
  w.acf[0] = 1.0;
  w.acf_bound = 1.96 / std::sqrt(static_cast<double>(n));
  double peak = -1.0;
  for (std::size_t lag = 1; lag <= max_lag; ++lag) {
    double c = 0.0;
    for (std::size_t k = 0; k + lag < n; ++k)
      c += x[k] * x[k + lag];
    w.acf[lag] = c0 > 0 ? c / c0 : 0.0;
    if (std::abs(w.acf[lag]) > w.acf_bound) ++w.acf_outside;
    if (std::abs(w.acf[lag]) > peak) peak = std::abs(w.acf[lag]), w.acf_peak_lag = lag;
  }
  w.acf_allowed = binomial_quantile(max_lag, 0.05, 0.99);
  w.acf_white = w.acf_outside <= w.acf_allowed;
  // Cumulated periodogram (R's cpgram: split cosine bell taper over 10 % at each end).
  const auto m = static_cast<std::size_t>(std::floor(0.1 * static_cast<double>(n)));
  for (std::size_t k = 0; k < m; ++k) {
    const double wgt = 0.5 * (1 - std::cos(std::numbers::pi * (2.0 * static_cast<double>(k) + 1) /
                                           (2.0 * static_cast<double>(m))));
    x[k] *= wgt;
    x[n - 1 - k] *= wgt;
  }
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, x);
  std::size_t len = n / 2 + 1; // frequencies 0 .. n/2
  if (len % 2 == 0) --len;     // as R: an even count drops the last
  std::vector<double> power(len);
  for (std::size_t k = 1; k < len; ++k)
    power[k] = std::norm(spectrum[k]) / static_cast<double>(n);
  double total = 0.0;
  for (double p : power)
    total += p;
  w.frequency.resize(len);
  w.cumulated.resize(len);
  double run = 0.0;
  const double nyquist = 0.5 / dt;
  const auto mp = static_cast<double>(len - 1);
  w.ks_bound = 1.358 / (std::sqrt(mp) + 0.12 + 0.11 / std::sqrt(mp));
  for (std::size_t k = 0; k < len; ++k) {
    run += power[k];
    w.frequency[k] = static_cast<double>(k) / (static_cast<double>(n) * dt);
    w.cumulated[k] = total > 0 ? run / total : 0.0;
    w.ks_max = std::max(w.ks_max, std::abs(w.cumulated[k] - w.frequency[k] / nyquist));
  }
  w.cpgram_white = w.ks_max <= w.ks_bound;
  return w;
}

} // namespace thermnet
