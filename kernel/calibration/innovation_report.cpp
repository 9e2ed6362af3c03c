// The whiteness tests of every filtered series, and their JSON and text.

#include "kernel/calibration/innovation_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet {

std::vector<SeriesWhiteness> test_innovations(const std::vector<CaseInnovations>& cases) {
  std::vector<SeriesWhiteness> out;
  for (const auto& c : cases) {
    std::vector<double> dt;
    for (std::size_t k = 1; k < c.times.size(); ++k)
      dt.push_back(c.times[k] - c.times[k - 1]);
    double step = 1.0;
    if (!dt.empty()) {
      std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
      step = dt[dt.size() / 2];
    }
    for (std::size_t s = 0; s < c.nodes.size(); ++s) {
      std::vector<double> e;
      for (std::size_t k = 0; k < c.times.size(); ++k)
        if (!std::isnan(c.measured[s][k]) && !std::isnan(c.predicted[s][k]))
          e.push_back(c.measured[s][k] - c.predicted[s][k]);
      double ss = 0.0;
      for (double v : e)
        ss += v * v;
      const double rms = e.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(e.size()));
      out.push_back({c.case_name, c.nodes[s], rms, test_whiteness(e, step)});
    }
  }
  return out;
}

double one_step_rmse(const std::vector<CaseInnovations>& cases) {
  double ss = 0.0;
  std::size_t n = 0;
  for (const auto& c : cases)
    for (std::size_t s = 0; s < c.nodes.size(); ++s)
      for (std::size_t k = 0; k < c.times.size(); ++k)
        if (!std::isnan(c.measured[s][k]) && !std::isnan(c.predicted[s][k])) {
          const double e = c.measured[s][k] - c.predicted[s][k];
          ss += e * e;
          ++n;
        }
  return n ? std::sqrt(ss / static_cast<double>(n)) : 0.0;
}

nlohmann::ordered_json whiteness_json(const std::vector<SeriesWhiteness>& tests) {
  auto arr = nlohmann::ordered_json::array();
  for (const auto& s : tests) {
    const Whiteness& w = s.test;
    nlohmann::ordered_json j;
    j["case"] = s.case_name;
    j["node"] = s.node;
    j["n"] = w.n;
    j["innovation_rms"] = s.innovation_rms;
    j["white"] = w.white();
    j["acf"] = {{"bound", w.acf_bound},
                {"outside", w.acf_outside},
                {"allowed", w.acf_allowed},
                {"peak_lag", w.acf_peak_lag},
                {"peak_lag_s", static_cast<double>(w.acf_peak_lag) * w.dt},
                {"white", w.acf_white},
                {"values", w.acf}};
    j["cpgram"] = {{"bound", w.ks_bound},
                   {"max_deviation", w.ks_max},
                   {"white", w.cpgram_white},
                   {"frequency", w.frequency},
                   {"cumulated", w.cumulated}};
    arr.push_back(std::move(j));
  }
  return arr;
}

std::string whiteness_text(const std::vector<SeriesWhiteness>& tests) {
  std::string out;
  for (const auto& s : tests) {
    const Whiteness& w = s.test;
    const std::string where = fmt::format("{} in case {}", s.node, s.case_name);
    const std::string acf =
        fmt::format("autocorrelation: {} of {} lags outside ±{:.3f} (white noise: at most {}; "
                    "largest at lag {} = {:.3g} h)",
                    w.acf_outside, w.acf.empty() ? 0 : w.acf.size() - 1, w.acf_bound, w.acf_allowed,
                    w.acf_peak_lag, static_cast<double>(w.acf_peak_lag) * w.dt / 3600.0);
    const std::string cp = fmt::format(
        "cumulated periodogram: largest deviation {:.3f} (Kolmogorov-Smirnov bound {:.3f})",
        w.ks_max, w.ks_bound);
    out += fmt::format("  {}: one-step RMS {:.4g} K, innovations {}\n    {} [{}]\n    {} [{}]\n",
                       where, s.innovation_rms, w.white() ? "white" : "NOT white", acf,
                       w.acf_white ? "pass" : "FAIL", cp, w.cpgram_white ? "pass" : "FAIL");
  }
  return out;
}

} // namespace thermnet
