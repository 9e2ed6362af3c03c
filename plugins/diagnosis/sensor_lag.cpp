// Hypothesis 'sensor_lag': a sensor reads its node through a first-order lag (time constant tau).
// Measurement-side: the simulated series is passed through the lag; the start comes from the
// residual regressed on the simulated slope (T_meas ~ T_sim - tau dT_sim/dt).
#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/diagnosis/hypothesis.hpp"
#include "kernel/diagnosis/sensor_statements.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet {
namespace {

class SensorLag final : public Hypothesis {
public:
  std::vector<Candidate> propose(const Evidence& ev) const override { return proposals(ev, false); }

  // A lag has one parameter, and the filter sees it whatever the simulation's error looks like:
  // every measured node's is tested (from two sampling intervals where the screen found none).
  std::vector<Candidate> propose_for_likelihood(const Evidence& ev) const override {
    return proposals(ev, true);
  }

private:
  static std::vector<Candidate> proposals(const Evidence& ev, bool unscreened) {
    std::vector<Candidate> out;
    if (ev.cases.empty()) return out;
    const auto& nodes = ev.cases.front().spec.nodes;
    for (int a = 0; a < static_cast<int>(nodes.size()); ++a) {
      if (nodes[static_cast<std::size_t>(a)].boundary) continue;
      double rs = 0.0, ss = 0.0;
      bool any = false;
      for (const auto& ce : ev.cases)
        for (std::size_t s = 0; s < ce.measured.series.size(); ++s) {
          if (ce.measured.series[s].node_index != a) continue;
          std::vector<double> sm, slope;
          smooth_series(ce.times(), ce.simulated[s], 2, sm, slope);
          for (std::size_t k = 0; k < ce.times().size(); ++k) {
            const double m = ce.measured.series[s].values[k];
            if (std::isnan(m) || !std::isfinite(slope[k])) continue;
            rs += (ce.simulated[s][k] - m) * slope[k];
            ss += slope[k] * slope[k];
            any = true;
          }
        }
      const bool screened = any && ss > 0.0 && rs > 0.0;
      if (!screened && !(unscreened && any)) continue;
      Candidate c;
      c.kind = "sensor_lag";
      c.nodes = {nodes[static_cast<std::size_t>(a)].name};
      c.names = {"tau"};
      c.lo = {1e-3};
      c.hi = {1e6};
      c.start = {screened ? std::clamp(rs / ss, 1e-2, 1e5)
                          : std::clamp(2.0 * sampling_interval(ev), 1e-2, 1e5)};
      c.measurement_side = true;
      c.screen = screened ? rs * rs / ss : 0.0;
      c.index = {a};
      c.evidence = screened ? fmt::format("{} measured lags the simulation by about {:.3g} s",
                                          c.nodes[0], c.start[0])
                            : fmt::format("{} is measured: its sensor may lag it", c.nodes[0]);
      out.push_back(std::move(c));
    }
    return out;
  }

public:
  void correct(const Candidate& c, const std::vector<double>& p, int node,
               const std::vector<double>& t, std::vector<double>& x) const override {
    if (node != c.index[0] || x.empty()) return;
    // Exact first-order lag of a piecewise linear input: y' = (x - y) / tau.
    const double tau = p[0];
    double y = x[0];
    for (std::size_t k = 1; k < x.size(); ++k) {
      const double h = t[k] - t[k - 1];
      const double E = std::exp(-h / tau);
      const double slope = h > 0 ? (x[k] - x[k - 1]) / h : 0.0;
      const double yk = x[k] - slope * tau + (y - x[k - 1] + slope * tau) * E;
      x[k - 1] = y;
      y = yk;
    }
    x.back() = y;
  }

  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    return sensor_statement(ev, "sensor_lag", c.nodes[0], "tau", p[0], "s");
  }

  CaseLines case_statements(const Candidate& c, const std::vector<double>& p,
                            const Evidence& ev) const override {
    return sensor_case_lines(ev, c.nodes[0], "tau", p[0], "s");
  }
};

HypothesisPlugin make_sensor_lag() {
  return {.name = "sensor_lag",
          .doc = "a sensor reads its node through a first-order lag (s)",
          .create = [] { return std::make_unique<SensorLag>(); },
          .screen = "the residual against the simulated slope",
          .fitted = "tau [s]",
          .writes = "sensor diag_sensor_lag_a a tau = ... (or the key of a sensor the model has, "
                    "in every case)"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_sensor_lag);
} // namespace thermnet
