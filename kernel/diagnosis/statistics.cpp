// Statistics of the diagnosis: autocorrelation time of residuals and the comparison of two fits.

#include "kernel/diagnosis/statistics.hpp"

#include <Eigen/Core>
#include <boost/math/distributions/normal.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermnet {

double sum_of_squares(const StoredResiduals& r) {
  double s = 0.0;
  for (double x : r)
    s += x * x;
  return s;
}

template <class T>
double autocorrelation_time(const std::vector<std::vector<T>>& series, double cap) {
  double lag0 = 0.0, lag1 = 0.0;
  for (const auto& s : series) {
    if (s.size() < 2) continue;
    double mean = 0.0;
    for (double x : s)
      mean += x;
    mean /= static_cast<double>(s.size());
    for (std::size_t k = 0; k < s.size(); ++k) {
      const double a = s[k] - mean;
      lag0 += a * a;
      if (k + 1 < s.size()) lag1 += a * (s[k + 1] - mean);
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

namespace {

/// The runs of a series of n values: the given lengths, or the whole series.
std::vector<std::size_t> runs_of(std::size_t n, const std::vector<std::size_t>& segments) {
  return segments.empty() ? std::vector<std::size_t>{n} : segments;
}

/// sum over k of x[k] x[k + lag] for the n values from x (lag < n). A dot product of the series
/// with itself shifted, vectorised: the lagged sums over a 72-node panel's 115,200 held-out
/// points at up to 1,000 lags were a tenth of its diagnosis's CPU time one product at a time.
double lagged_dot(const double* x, std::size_t n, std::size_t lag) {
  const auto m = static_cast<Eigen::Index>(n - lag);
  return Eigen::Map<const Eigen::VectorXd>(x, m).dot(Eigen::Map<const Eigen::VectorXd>(x + lag, m));
}

} // namespace

template <class T>
std::vector<double> positive_autocorrelation(const std::vector<T>& values,
                                             const std::vector<std::size_t>& segments,
                                             std::size_t max_lag) {
  const std::vector<std::size_t> runs = runs_of(values.size(), segments);
  std::vector<double> c(values.size());
  double lag0 = 0.0;
  std::size_t from = 0, longest = 0;
  for (std::size_t len : runs) {
    if (from + len > values.size()) break;
    double mean = 0.0;
    for (std::size_t k = from; k < from + len; ++k)
      mean += values[k];
    mean /= static_cast<double>(std::max<std::size_t>(1, len));
    for (std::size_t k = from; k < from + len; ++k) {
      c[k] = values[k] - mean;
      lag0 += c[k] * c[k];
    }
    from += len;
    longest = std::max(longest, len);
  }
  std::vector<double> rho;
  if (!(lag0 > 0.0)) return rho;
  for (std::size_t lag = 1; lag <= max_lag && lag < longest; ++lag) {
    double sum = 0.0;
    from = 0;
    for (std::size_t len : runs) {
      if (from + len > c.size()) break;
      if (lag < len) sum += lagged_dot(c.data() + from, len, lag);
      from += len;
    }
    const double r = sum / lag0;
    if (!(r > 0.0)) break;
    rho.push_back(r);
  }
  return rho;
}

template <class T>
double holdout_gain_z(const std::vector<T>& reference, const std::vector<T>& candidate,
                      double noise, const std::vector<std::size_t>& segments) {
  if (reference.empty() || reference.size() != candidate.size() || !(noise > 0.0)) return 0.0;
  return holdout_gain_z(reference, candidate,
                        positive_autocorrelation(candidate, runs_of(candidate.size(), segments)),
                        noise, segments);
}

template <class T>
double holdout_gain_z(const std::vector<T>& reference, const std::vector<T>& candidate,
                      const std::vector<double>& rho, double noise,
                      const std::vector<std::size_t>& segments) {
  if (reference.empty() || reference.size() != candidate.size() || !(noise > 0.0)) return 0.0;
  const std::vector<std::size_t> runs = runs_of(reference.size(), segments);
  double gain = 0.0, cand2 = 0.0, dd = 0.0, cross = 0.0;
  std::vector<double> d(reference.size());
  std::size_t from = 0;
  for (std::size_t len : runs) {
    if (from + len > reference.size()) break;
    for (std::size_t i = from; i < from + len; ++i) {
      const double ref = reference[i], cand = candidate[i];
      d[i] = ref - cand;
      dd += d[i] * d[i];
      gain += ref * ref - cand * cand;
      cand2 += cand * cand;
    }
    for (std::size_t lag = 1; lag <= rho.size() && lag < len; ++lag)
      cross += rho[lag - 1] * lagged_dot(d.data() + from, len, lag);
    from += len;
  }
  // (a truncated autocorrelation need not be positive definite: never below the white value)
  const double dRd = std::max(dd, dd + 2.0 * cross);
  if (!(dRd > 0.0)) return 0.0;
  const double s2 = std::max(noise * noise, cand2 / static_cast<double>(candidate.size()));
  return gain / (2.0 * std::sqrt(s2 * dRd));
}

double significant_gain_z_for(std::size_t compared) {
  const double p = 0.01 / static_cast<double>(std::max<std::size_t>(1, compared));
  const double z = boost::math::quantile(boost::math::complement(boost::math::normal(), p));
  return std::min(significant_gain_z, z);
}

template <class T>
double largest_window_gain(const std::vector<std::vector<T>>& reference,
                           const std::vector<std::vector<T>>& candidate, std::size_t window) {
  double best = 0.0;
  for (std::size_t s = 0; s < reference.size() && s < candidate.size(); ++s) {
    const auto& r = reference[s];
    const auto& c = candidate[s];
    if (r.size() != c.size() || r.empty()) continue;
    const std::size_t w = std::min(window, r.size());
    double sr = 0.0, sc = 0.0;
    const auto sq = [](double x) { return x * x; };
    for (std::size_t k = 0; k < r.size(); ++k) {
      sr += sq(r[k]), sc += sq(c[k]);
      if (k >= w) sr -= sq(r[k - w]), sc -= sq(c[k - w]);
      if (k + 1 >= w)
        best = std::max(best, std::sqrt(std::max(sr, 0.0) / static_cast<double>(w)) -
                                  std::sqrt(std::max(sc, 0.0) / static_cast<double>(w)));
    }
  }
  return best;
}

template <class T>
double worst_block_gain(const std::vector<T>& reference, const std::vector<T>& candidate,
                        const std::vector<std::size_t>& blocks) {
  std::size_t total = 0;
  for (std::size_t n : blocks)
    total += n;
  if (blocks.empty() || total != reference.size() || total != candidate.size())
    return -std::numeric_limits<double>::infinity();
  double worst = std::numeric_limits<double>::infinity();
  std::size_t at = 0;
  for (std::size_t n : blocks) {
    double ref = 0.0, cand = 0.0;
    for (std::size_t k = at; k < at + n; ++k) {
      const double a = reference[k], b = candidate[k];
      ref += a * a;
      cand += b * b;
    }
    at += n;
    if (n == 0) continue;
    worst = std::min(worst, ref > 0.0 ? 1.0 - std::sqrt(cand / ref) : -1.0);
  }
  return std::isfinite(worst) ? worst : -std::numeric_limits<double>::infinity();
}

// The residuals' two precisions: double (computed) and float (StoredResiduals).
#define THERMNET_STATISTICS_FOR(T)                                                                 \
  template double autocorrelation_time(const std::vector<std::vector<T>>&, double);                \
  template std::vector<double> positive_autocorrelation(                                           \
      const std::vector<T>&, const std::vector<std::size_t>&, std::size_t);                        \
  template double holdout_gain_z(const std::vector<T>&, const std::vector<T>&, double,             \
                                 const std::vector<std::size_t>&);                                 \
  template double holdout_gain_z(const std::vector<T>&, const std::vector<T>&,                     \
                                 const std::vector<double>&, double,                               \
                                 const std::vector<std::size_t>&);                                 \
  template double largest_window_gain(const std::vector<std::vector<T>>&,                          \
                                      const std::vector<std::vector<T>>&, std::size_t);            \
  template double worst_block_gain(const std::vector<T>&, const std::vector<T>&,                   \
                                   const std::vector<std::size_t>&);
THERMNET_STATISTICS_FOR(double)
THERMNET_STATISTICS_FOR(float)
#undef THERMNET_STATISTICS_FOR

} // namespace thermnet
