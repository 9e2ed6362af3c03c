// How far a model's simulation is from the data: RMSE, bias, largest error and trend disagreement
// per node and case, whether that is measurement noise only, and the trend in words.

#include "kernel/diagnosis/engine.hpp"

#include <boost/math/distributions/chi_squared.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermnet::detail {

namespace {

/// Consecutive measured samples over which the floor test also looks for a local error.
constexpr std::size_t kWindow = 10;

/// The largest RMS of sim - meas over kWindow consecutive measured samples (all of them when
/// fewer): an error confined to a short span (an event, a step) that the whole series' RMSE
/// dilutes.
double window_rmse(const std::vector<double>& meas, const std::vector<double>& sim) {
  std::vector<double> e2;
  for (std::size_t k = 0; k < meas.size(); ++k)
    if (!std::isnan(meas[k])) e2.push_back((sim[k] - meas[k]) * (sim[k] - meas[k]));
  if (e2.empty()) return 0.0;
  const std::size_t w = std::min(kWindow, e2.size());
  double sum = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < e2.size(); ++k) {
    sum += e2[k];
    if (k >= w) sum -= e2[k - w];
    if (k + 1 >= w) worst = std::max(worst, sum);
  }
  return std::sqrt(std::max(worst, 0.0) / static_cast<double>(w));
}

/// Error sums of one series (sim - meas over the measured points) and its largest error.
NodeMetrics series_errors(const std::vector<double>& t, const std::vector<double>& meas,
                          const std::vector<double>& sim, const std::string& case_name, double& e2,
                          double& e1) {
  NodeMetrics nm;
  e2 = 0.0, e1 = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (std::isnan(meas[k])) continue;
    const double e = sim[k] - meas[k];
    e2 += e * e, e1 += e, ++nm.points;
    if (std::abs(e) > std::abs(nm.max_error)) nm.max_error = e, nm.max_error_time = t[k];
  }
  nm.max_error_case = case_name;
  nm.window_rmse = window_rmse(meas, sim);
  if (nm.points) {
    nm.rmse = std::sqrt(e2 / static_cast<double>(nm.points));
    nm.bias = e1 / static_cast<double>(nm.points);
  }
  return nm;
}

/// Trend disagreement: stretches (>= 3 samples) where the measured and simulated slopes have
/// opposite signs, both beyond the noise of a slope estimate.
void add_trend_mismatch(NodeMetrics& nm, const std::vector<double>& t,
                        const std::vector<double>& meas, const std::vector<double>& sim,
                        double noise, const std::string& case_name) {
  const double dt =
      (t.back() - t.front()) / static_cast<double>(std::max<std::size_t>(1, t.size() - 1));
  std::vector<double> sm, slm, ss, sls;
  smooth_series(t, meas, 4, sm, slm);
  smooth_series(t, sim, 2, ss, sls);
  const double th = 3.0 * noise * 0.13 / std::max(dt, 1e-9);
  auto bad = [&](std::size_t j) {
    return std::isfinite(slm[j]) && std::isfinite(sls[j]) && std::abs(slm[j]) > th &&
           std::abs(sls[j]) > th * 0.1 && slm[j] * sls[j] < 0.0;
  };
  std::size_t k = 0;
  while (k < t.size()) {
    if (!bad(k)) {
      ++k;
      continue;
    }
    std::size_t e = k;
    while (e + 1 < t.size() && bad(e + 1))
      ++e;
    if (e >= k + 2) {
      const double len = t[e] - t[k];
      nm.trend_mismatch_s += len;
      if (len > nm.longest_mismatch_s) {
        nm.longest_mismatch_s = len;
        nm.longest_mismatch_start = t[k];
        nm.longest_mismatch_case = case_name;
        nm.measured_rising = slm[k] > 0.0;
      }
    }
    k = e + 1;
  }
}

/// Adds one case's metrics of a node to its every-case total (RMSE and bias are set from the
/// sums at the end).
void add_to_total(NodeMetrics& tot, const NodeMetrics& nm, const std::string& case_name) {
  tot.points += nm.points;
  tot.window_rmse = std::max(tot.window_rmse, nm.window_rmse);
  if (std::abs(nm.max_error) > std::abs(tot.max_error))
    tot.max_error = nm.max_error, tot.max_error_time = nm.max_error_time,
    tot.max_error_case = case_name;
  tot.trend_mismatch_s += nm.trend_mismatch_s;
  if (nm.longest_mismatch_s > tot.longest_mismatch_s) {
    tot.longest_mismatch_s = nm.longest_mismatch_s;
    tot.longest_mismatch_start = nm.longest_mismatch_start;
    tot.longest_mismatch_case = nm.longest_mismatch_case;
    tot.measured_rising = nm.measured_rising;
  }
}

} // namespace

FitMetrics Engine::metrics(const CaseSims& sims) const {
  FitMetrics fm;
  double sse = 0.0;
  std::size_t n = 0;
  std::map<std::string, double> node_sse, node_sum;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    const CaseEvidence& ce = ev_.cases[c];
    for (std::size_t s = 0; s < ce.measured.series.size(); ++s) {
      const auto& meas = ce.measured.series[s].values;
      double e2 = 0.0, e1 = 0.0;
      NodeMetrics nm = series_errors(ce.times(), meas, sims[c][s], ce.name, e2, e1);
      add_trend_mismatch(nm, ce.times(), meas, sims[c][s], ev_.noise_floor, ce.name);
      const std::string& name = ce.measured.series[s].node;
      node_sse[name] += e2, node_sum[name] += e1;
      add_to_total(fm.nodes[name], nm, ce.name);
      fm.cases[ce.name][name] = nm;
      sse += e2, n += nm.points;
    }
  }
  for (auto& [name, nm] : fm.nodes)
    if (nm.points) {
      nm.rmse = std::sqrt(node_sse[name] / static_cast<double>(nm.points));
      nm.bias = node_sum[name] / static_cast<double>(nm.points);
    }
  fm.rmse = n ? std::sqrt(sse / static_cast<double>(n)) : 0.0;
  const double total = sst(Part{});
  fm.r2 = total > 0 ? 1.0 - sse / total : std::numeric_limits<double>::quiet_NaN(); // no spread
  return fm;
}

} // namespace thermnet::detail

namespace thermnet {

double FitMetrics::worst_window_rmse() const {
  double worst = 0.0;
  for (const auto& [name, nm] : nodes)
    worst = std::max(worst, nm.window_rmse);
  return worst;
}

} // namespace thermnet

namespace thermnet::detail {

bool Engine::at_floor(const FitMetrics& m) const {
  // Nothing is wrong when the whole fit, every node and every span of kWindow samples are within
  // the measurement noise. A span's sum of squares is sigma^2 chi^2(kWindow) under noise alone;
  // its limit is that distribution's quantile at 1 % over the number of spans looked at (a
  // Bonferroni bound), so noise alone passes a whole diagnosis with at least 99 % probability.
  // The spans slide by one sample (window_rmse), so there are about as many as measured points:
  // counting only the disjoint ones (a tenth as many) let pure noise fail the test in 4 % of
  // diagnoses of 120 series of 961 samples (simulated), and a 72-node panel fitted to its noise
  // (RMSE 0.309 K, noise 0.31 K, worst span 2.25 sigma against a limit of 2.17) went on searching.
  const double nf = ev_.noise_floor;
  const double worst_window = m.worst_window_rmse();
  double worst = 0.0, points = 0.0;
  for (const auto& [name, nm] : m.nodes) {
    worst = std::max(worst, nm.rmse);
    points += static_cast<double>(nm.points);
  }
  const double spans = std::max(1.0, points);
  const boost::math::chi_squared chi2(static_cast<double>(kWindow));
  const double window_limit =
      nf * std::sqrt(boost::math::quantile(boost::math::complement(chi2, 0.01 / spans)) /
                     static_cast<double>(kWindow));
  return nf > 0 && m.rmse <= 1.25 * nf && worst <= 1.6 * nf && worst_window <= window_limit;
}

std::string Engine::trend_words(const FitMetrics& m, const std::vector<std::string>& nodes) const {
  const NodeMetrics* best = nullptr;
  std::string who;
  for (const auto& name : nodes) {
    auto it = m.nodes.find(name);
    if (it != m.nodes.end() && it->second.longest_mismatch_s > 0 &&
        (!best || it->second.longest_mismatch_s > best->longest_mismatch_s))
      best = &it->second, who = name;
  }
  if (!best) return {};
  return fmt::format("{} measured {} for {:.0f} s from t = {:.0f} s (case {}) while simulated {}",
                     who, best->measured_rising ? "rises" : "falls", best->longest_mismatch_s,
                     best->longest_mismatch_start, best->longest_mismatch_case,
                     best->measured_rising ? "falls" : "rises");
}

} // namespace thermnet::detail
