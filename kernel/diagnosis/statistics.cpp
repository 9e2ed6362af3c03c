// Statistics of the diagnosis: autocorrelation time of residuals and the comparison of two fits.

#include "kernel/diagnosis/statistics.hpp"

#include <algorithm>
#include <cmath>

namespace thermnet {

double autocorrelation_time(const std::vector<std::vector<double>>& series, double cap) {
  double lag0 = 0.0, lag1 = 0.0;
  for (const auto& s : series) {
    if (s.size() < 2) continue;
    double mean = 0.0;
    for (double x : s)
      mean += x;
    mean /= static_cast<double>(s.size());
    for (std::size_t k = 0; k < s.size(); ++k) {
      lag0 += (s[k] - mean) * (s[k] - mean);
      if (k + 1 < s.size()) lag1 += (s[k] - mean) * (s[k + 1] - mean);
    }
  }
  if (lag0 <= 0.0) return 1.0;
  const double rho = std::clamp(lag1 / lag0, 0.0, 0.999);
  return std::clamp((1.0 + rho) / (1.0 - rho), 1.0, cap);
}

FitComparison compare_fits(const FitResiduals& a, const FitResiduals& b, double noise,
                           double threshold) {
  auto sse = [](const FitResiduals& f, std::size_t& n) {
    double s = 0.0;
    for (const auto& v : f.series)
      for (double x : v)
        s += x * x, ++n;
    return s;
  };
  std::size_t na = 0, nb = 0;
  const double sa = sse(a, na), sb = sse(b, nb);
  FitComparison c;
  c.first_better = sa <= sb;
  const FitResiduals& better = c.first_better ? a : b;
  const double n = static_cast<double>(std::max<std::size_t>(1, na));
  c.tau = autocorrelation_time(better.series);
  c.n_eff = n / c.tau;
  const double s2 = std::max(noise * noise, std::min(sa, sb) / n);
  if (s2 > 0.0) c.z = std::abs(sb - sa) / c.tau / (s2 * std::sqrt(2.0 * c.n_eff));
  c.holdout_agrees = c.first_better ? a.holdout_sse < b.holdout_sse : b.holdout_sse < a.holdout_sse;
  c.separable = c.z >= threshold && c.holdout_agrees;
  return c;
}

double holdout_gain_z(const std::vector<double>& reference, const std::vector<double>& candidate,
                      double noise) {
  if (reference.empty() || reference.size() != candidate.size() || !(noise > 0.0)) return 0.0;
  double gain = 0.0, diff2 = 0.0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    gain += reference[i] * reference[i] - candidate[i] * candidate[i];
    diff2 += (reference[i] - candidate[i]) * (reference[i] - candidate[i]);
  }
  if (diff2 <= 0.0) return 0.0;
  return gain / (2.0 * noise * std::sqrt(diff2));
}

} // namespace thermnet
