// The signature of the error left after the findings: its autocorrelation, the period of the
// sinusoid that explains most of it (a periodogram by least squares on the measured times, which
// need not be even), and its correlation with every input at every lag. A 24 h period, or a
// correlation with the solar gain at a lag, points to the daily input a model misses.

#include "kernel/diagnosis/engine.hpp"

#include "kernel/diagnosis/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace thermnet::detail {

namespace {

/// One measured series' residual (sim - meas) with its times; NaN samples left out.
struct Residual {
  std::vector<double> t, r;
  std::size_t case_index = 0;
};

/// Centred copy.
std::vector<double> centred(std::vector<double> v) {
  double m = 0.0;
  for (double x : v)
    m += x;
  m /= static_cast<double>(std::max<std::size_t>(1, v.size()));
  for (double& x : v)
    x -= m;
  return v;
}

/// Pooled autocorrelation at a lag of `lag` samples.
double autocorrelation_at(const std::vector<Residual>& rs, std::size_t lag) {
  double num = 0.0, den = 0.0;
  for (const auto& s : rs) {
    const auto c = centred(s.r);
    for (std::size_t k = 0; k < c.size(); ++k) {
      den += c[k] * c[k];
      if (k + lag < c.size()) num += c[k] * c[k + lag];
    }
  }
  return den > 0.0 ? num / den : 0.0;
}

/// The share of the residuals' sum of squares a sinusoid of period P (its own amplitude and
/// phase per series, a constant too) explains.
double sinusoid_share(const std::vector<Residual>& rs, double P) {
  double before = 0.0, after = 0.0;
  for (const auto& s : rs) {
    const auto c = centred(s.r);
    double cc = 0.0, ss = 0.0, cs = 0.0, yc = 0.0, ys = 0.0, sc = 0.0, sn = 0.0;
    const double w = 2.0 * std::numbers::pi / P;
    const double n = static_cast<double>(c.size());
    for (std::size_t k = 0; k < c.size(); ++k) {
      const double co = std::cos(w * s.t[k]), si = std::sin(w * s.t[k]);
      cc += co * co, ss += si * si, cs += co * si, yc += c[k] * co, ys += c[k] * si;
      sc += co, sn += si;
      before += c[k] * c[k];
    }
    // Least squares on cos, sin and a constant (the constant's column removed first).
    if (n < 4) {
      for (double x : c)
        after += x * x;
      continue;
    }
    cc -= sc * sc / n, ss -= sn * sn / n, cs -= sc * sn / n;
    const double det = cc * ss - cs * cs;
    double explained = 0.0;
    if (det > 1e-12 * std::max(1.0, cc * ss)) {
      const double a = (yc * ss - ys * cs) / det, b = (ys * cc - yc * cs) / det;
      explained = a * yc + b * ys;
    }
    double own = 0.0;
    for (double x : c)
      own += x * x;
    after += std::max(0.0, own - explained);
  }
  return before > 0.0 ? 1.0 - after / before : 0.0;
}

} // namespace

StructuralError residual_signature(const Evidence& ev, const CaseSims& sims, double rmse) {
  StructuralError out;
  out.rmse = rmse;
  std::vector<Residual> rs;
  double dt = 0.0, span = 0.0;
  std::vector<double> steps;
  for (std::size_t c = 0; c < ev.cases.size(); ++c) {
    const auto& m = ev.cases[c].measured;
    for (std::size_t s = 0; s < m.series.size(); ++s) {
      if (ev.cases[c].spec.nodes[static_cast<std::size_t>(m.series[s].node_index)].boundary)
        continue;
      Residual r;
      r.case_index = c;
      for (std::size_t k = 0; k < m.times.size(); ++k)
        if (!std::isnan(m.series[s].values[k])) {
          r.t.push_back(m.times[k]);
          r.r.push_back(sims[c][s][k] - m.series[s].values[k]);
        }
      for (std::size_t k = 1; k < r.t.size(); ++k)
        steps.push_back(r.t[k] - r.t[k - 1]);
      if (r.t.size() >= 2) span = std::max(span, r.t.back() - r.t.front());
      if (r.t.size() >= 8) rs.push_back(std::move(r));
    }
  }
  if (rs.empty() || steps.empty()) return out;
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  dt = steps[steps.size() / 2];
  std::size_t n = 0, shortest = rs.front().r.size();
  std::vector<std::vector<double>> series;
  for (const auto& s : rs) {
    n += s.r.size();
    shortest = std::min(shortest, s.r.size());
    series.push_back(s.r);
  }
  out.independent = static_cast<double>(n) / autocorrelation_time(series);
  for (std::size_t lag : {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000})
    if (lag < shortest / 2)
      out.autocorrelation.emplace_back(static_cast<double>(lag) * dt, autocorrelation_at(rs, lag));
  // Periods from four samples to two thirds of the longest series, 40 per decade.
  for (double P = 4.0 * dt; P <= span / 1.5 && dt > 0.0; P *= std::pow(10.0, 1.0 / 40.0)) {
    const double share = sinusoid_share(rs, P);
    if (share > out.period_share) out.period_share = share, out.period_s = P;
  }
  // Every input's correlation with the residual at lags from 0 to a quarter of the shortest
  // series (at most 200 samples), the input leading.
  const auto& spec = ev.cases.front().spec;
  const std::size_t max_lag = std::min<std::size_t>(200, shortest / 4);
  auto input_values = [&](std::size_t c, const std::string& name, const std::vector<double>& t) {
    const auto& cs = ev.cases[c].spec;
    std::vector<double> u;
    const int node = cs.node_index(name);
    const lang::Signal* sig = nullptr;
    if (node >= 0) {
      sig = &cs.nodes[static_cast<std::size_t>(node)].T;
    } else {
      const std::string el = name.substr(0, name.size() - 2); // "NAME.P"
      for (const auto& e : cs.elements)
        if (e.name == el && e.has("P")) sig = &e.values.at("P");
    }
    for (double x : t)
      u.push_back(sig ? sig->at(x) : 0.0);
    return u;
  };
  std::vector<std::string> inputs;
  for (const auto& nd : spec.nodes)
    if (nd.boundary) inputs.push_back(nd.name);
  for (const auto& e : spec.elements)
    if (!e.name.empty() && e.has("P") && e.nodes().size() == 1) inputs.push_back(e.name + ".P");
  std::vector<std::vector<double>> cr;
  for (const auto& s : rs)
    cr.push_back(centred(s.r));
  for (const auto& name : inputs) {
    StructuralError::Input best{name, 0.0, 0.0};
    std::vector<std::vector<double>> us;
    for (const auto& s : rs)
      us.push_back(centred(input_values(s.case_index, name, s.t)));
    for (std::size_t lag = 0; lag <= max_lag; ++lag) {
      double num = 0.0, rr = 0.0, uu = 0.0;
      for (std::size_t i = 0; i < rs.size(); ++i) {
        const auto& c = cr[i];
        for (std::size_t k = lag; k < c.size(); ++k) {
          num += c[k] * us[i][k - lag];
          rr += c[k] * c[k];
          uu += us[i][k - lag] * us[i][k - lag];
        }
      }
      if (!(rr > 0.0) || !(uu > 0.0)) continue;
      const double r = num / std::sqrt(rr * uu);
      if (std::abs(r) > std::abs(best.r)) best.r = r, best.lag_s = static_cast<double>(lag) * dt;
    }
    if (best.r != 0.0) out.inputs.push_back(best);
  }
  std::stable_sort(out.inputs.begin(), out.inputs.end(),
                   [](const auto& a, const auto& b) { return std::abs(a.r) > std::abs(b.r); });
  return out;
}

} // namespace thermnet::detail
