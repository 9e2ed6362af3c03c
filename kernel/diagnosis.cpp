// The diagnosis engine: baseline metrics, noise floor, the screen on unexplained heat flows,
// simulation refits of the best candidates, validation on a held-back stretch, significance and
// ranking. The hypotheses themselves live in plugins/diagnosis/.

#include "kernel/diagnosis.hpp"

#include "kernel/element_registry.hpp"
#include "kernel/integrator.hpp"
#include "kernel/network.hpp"
#include "kernel/optimizer.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <set>
#include <stdexcept>

namespace thermnet {

// ------------------------------------------------------------------------- registry, helpers

HypothesisRegistry& HypothesisRegistry::global() {
  static HypothesisRegistry r;
  return r;
}

void HypothesisRegistry::add(HypothesisPlugin plugin) {
  if (plugins_.count(plugin.name) != 0)
    throw std::invalid_argument("duplicate hypothesis kind '" + plugin.name + "'");
  std::string name = plugin.name;
  plugins_.emplace(std::move(name), std::move(plugin));
}

const HypothesisPlugin* HypothesisRegistry::find(const std::string& name) const {
  auto it = plugins_.find(name);
  return it == plugins_.end() ? nullptr : &it->second;
}

std::vector<std::string> HypothesisRegistry::names() const {
  std::vector<std::string> v;
  for (const auto& [name, p] : plugins_)
    v.push_back(name);
  return v;
}

std::string netlist_number(double v) {
  return fmt::format("{:.5g}", v);
}

lang::ElementSpec make_element(const std::string& kind, const std::string& name,
                               std::vector<int> nodes, const std::map<std::string, double>& keys) {
  lang::ElementSpec e;
  e.schema = ElementRegistry::global().find(kind);
  if (!e.schema) throw std::invalid_argument("no element kind '" + kind + "'");
  e.kind = kind;
  e.name = name;
  e.nodes = std::move(nodes);
  for (const auto& [k, v] : keys)
    e.values.emplace(k, lang::Signal::of(v));
  return e;
}

std::string unique_name(const lang::NetworkSpec& spec, const std::string& base) {
  auto taken = [&](const std::string& n) {
    if (spec.node_index(n) >= 0) return true;
    for (const auto& e : spec.elements)
      if (e.name == n) return true;
    return false;
  };
  std::string n = base;
  for (int i = 2; taken(n); ++i)
    n = fmt::format("{}_{}", base, i);
  return n;
}

ScreenFit Evidence::regress(
    const std::function<double(std::size_t c, int node, std::size_t k)>& basis) const {
  double qb = 0.0, bb = 0.0, qq = 0.0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const CaseEvidence& ce = cases[c];
    for (int node : ce.rows) {
      const double C = ce.spec.nodes[static_cast<std::size_t>(node)].C;
      for (std::size_t k = 0; k < ce.q.size(); ++k) {
        const double q = ce.q[k][static_cast<std::size_t>(node)];
        if (std::isnan(q)) continue;
        const double b = basis(c, node, k);
        if (!std::isfinite(b) || b == 0.0) {
          qq += q * q / (C * C);
          continue;
        }
        qb += q * b / (C * C);
        bb += b * b / (C * C);
        qq += q * q / (C * C);
      }
    }
  }
  ScreenFit f;
  if (bb <= 0.0) return f;
  f.coefficient = qb / bb;
  f.reduction = qb * qb / bb;
  f.correlation = qq > 0.0 ? qb / std::sqrt(bb * qq) : 0.0;
  return f;
}

int Evidence::node_index(const std::string& name) const {
  return cases.empty() ? -1 : cases.front().spec.node_index(name);
}

bool Evidence::measured(int node) const {
  for (const auto& c : cases)
    if (std::find(c.rows.begin(), c.rows.end(), node) != c.rows.end()) return true;
  return false;
}

double estimate_noise(const std::vector<double>& v) {
  std::vector<double> d;
  for (std::size_t k = 1; k + 1 < v.size(); ++k) {
    const double x = v[k + 1] - 2.0 * v[k] + v[k - 1];
    if (std::isfinite(x)) d.push_back(x);
  }
  if (d.size() < 5) return 0.0;
  auto median = [](std::vector<double> x) {
    std::nth_element(x.begin(), x.begin() + static_cast<long>(x.size() / 2), x.end());
    return x[x.size() / 2];
  };
  const double m = median(d);
  for (double& x : d)
    x = std::abs(x - m);
  return 1.4826 * median(d) / std::sqrt(6.0);
}

void smooth_series(const std::vector<double>& t, const std::vector<double>& v, int half,
                   std::vector<double>& smoothed, std::vector<double>& slope) {
  const std::size_t n = v.size();
  smoothed.assign(n, std::numeric_limits<double>::quiet_NaN());
  slope.assign(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a =
        k >= static_cast<std::size_t>(half) ? k - static_cast<std::size_t>(half) : 0;
    const std::size_t b = std::min(n - 1, k + static_cast<std::size_t>(half));
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    int used = 0;
    const double scale = std::max(1e-9, (t[b] - t[a]) / 2.0);
    for (std::size_t j = a; j <= b; ++j) {
      if (!std::isfinite(v[j])) continue;
      const double x = (t[j] - t[k]) / scale;
      const Eigen::Vector3d phi(1.0, x, x * x);
      A += phi * phi.transpose();
      y += phi * v[j];
      ++used;
    }
    if (used < 4) continue;
    const Eigen::Vector3d c = A.ldlt().solve(y);
    smoothed[k] = c[0];
    slope[k] = c[1] / scale;
  }
}

namespace {

using Series = std::vector<double>;
/// sims[case][series][k]: simulated temperature of each measured series at the measured times.
using CaseSims = std::vector<std::vector<Series>>;

/// Which points a residual covers.
enum class Part { all, fit, holdout };

SolverOptions diagnosis_solver() {
  SolverOptions s;
  s.rtol = 1e-7;
  s.atol = 1e-7;
  return s;
}

/// Simulates a case at the measured times: temperatures of every node (spec order), K.
std::vector<std::vector<double>> run_case(lang::NetworkSpec spec,
                                          const std::vector<double>& times) {
  std::vector<std::vector<double>> out;
  if (times.empty()) return out;
  Network net(std::move(spec));
  std::vector<double> T = net.initial_state();
  const SolverOptions solver = diagnosis_solver();
  if (net.spec().settings.initial_steady) solve_steady(net, T, 0.0, solver);
  std::vector<double> all(net.spec().nodes.size());
  integrate(
      net, T, 0.0, times.back(), times,
      [&](double t, const std::vector<double>& x) {
        net.expand(t, x.data(), all.data());
        out.push_back(all);
      },
      solver);
  if (out.size() != times.size())
    throw std::runtime_error(
        fmt::format("the simulation gave {} of the {} measured times", out.size(), times.size()));
  return out;
}

/// A model-side candidate refitted together with the model's ranged params (the joint refit):
/// parameters = the candidate's own, then every ranged param (the `parameter` candidate's).
class Joint final : public Hypothesis {
public:
  Joint(const Hypothesis* inner, Candidate ic, const Hypothesis* par, Candidate pc)
      : inner_(inner), ic_(std::move(ic)), par_(par), pc_(std::move(pc)) {}

  /// The joint candidate: the inner one with the ranged params appended (started at `ranged`).
  Candidate candidate(const std::vector<double>& ranged) const {
    Candidate c = ic_;
    c.names.insert(c.names.end(), pc_.names.begin(), pc_.names.end());
    c.start.insert(c.start.end(), ranged.begin(), ranged.end());
    c.lo.insert(c.lo.end(), pc_.lo.begin(), pc_.lo.end());
    c.hi.insert(c.hi.end(), pc_.hi.begin(), pc_.hi.end());
    return c;
  }
  std::vector<Candidate> propose(const Evidence&) const override { return {}; }
  lang::ParamValues overrides(const Candidate&, const std::vector<double>& p) const override {
    lang::ParamValues v = par_->overrides(pc_, tail(p));
    for (auto& [k, x] : inner_->overrides(ic_, head(p)))
      v.insert_or_assign(k, x);
    return v;
  }
  void extend(const Candidate&, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    inner_->extend(ic_, head(p), spec);
  }
  void correct(const Candidate&, const std::vector<double>& p, int node,
               const std::vector<double>& times, std::vector<double>& sim) const override {
    inner_->correct(ic_, head(p), node, times, sim);
  }
  std::string statement(const Candidate&, const std::vector<double>& p,
                        const Evidence& ev) const override {
    return inner_->statement(ic_, head(p), ev) + "\n# fitted jointly with the ranged params:\n" +
           par_->statement(pc_, tail(p), ev);
  }

private:
  std::vector<double> head(const std::vector<double>& p) const {
    return {p.begin(), p.begin() + static_cast<long>(ic_.start.size())};
  }
  std::vector<double> tail(const std::vector<double>& p) const {
    return {p.begin() + static_cast<long>(ic_.start.size()), p.end()};
  }
  const Hypothesis* inner_;
  Candidate ic_;
  const Hypothesis* par_;
  Candidate pc_;
};

/// The diagnosis of one model: evidence plus the machinery to evaluate candidates.
class Engine {
public:
  Engine(const lang::Model& model, const DiagnosisOptions& opt) : model_(model), opt_(opt) {}

  DiagnosisReport run();

private:
  struct Fit {
    bool ok = false;
    std::vector<double> p;
    std::vector<double> se;
    double sse = 0.0;
    std::size_t n = 0;
  };

  void collect_evidence();
  void build_screen(CaseEvidence& ce, const std::vector<std::vector<double>>& all,
                    double& screen_total);
  CaseSims simulate(const Hypothesis* h, const Candidate* c, const std::vector<double>& p) const;
  bool in_part(std::size_t c, std::size_t k, Part part) const;
  void residuals(const CaseSims& sims, Part part, std::vector<double>& r) const;
  double sst(Part part) const;
  Fit fit(const Hypothesis& h, const Candidate& c, std::vector<double> start, Part part,
          int max_iter = 30, double rtol = 1e-7) const;
  FitMetrics metrics(const CaseSims& sims) const;
  Finding evaluate(const Hypothesis& h, const Candidate& c, bool joint = false) const;
  std::string trend_words(const FitMetrics& m, const std::vector<std::string>& nodes) const;

  const lang::Model& model_;
  DiagnosisOptions opt_;
  Evidence ev_;
  CaseSims baseline_;
  std::vector<double> split_; // per case: first held-back time
  double sse_base_all_ = 0, sse_base_fit_ = 0, sse_base_hold_ = 0;
  std::size_t n_all_ = 0, n_fit_ = 0, n_hold_ = 0;
};

void Engine::collect_evidence() {
  ev_.model = &model_;
  std::vector<std::string> names = opt_.cases;
  const bool all = names.empty();
  if (all) {
    names = model_.case_names();
    if (names.empty()) names.push_back(model_.resolve_case(""));
  }
  std::set<std::string> seen;
  for (const auto& requested : names) {
    const std::string name = model_.resolve_case(requested);
    if (!seen.insert(name).second) continue;
    lang::NetworkSpec spec = model_.instantiate(name);
    if (spec.settings.data_path.empty()) {
      if (all) continue;
      throw DiagnosisError(fmt::format("case '{}' has no measured data (add `data \"file.csv\"` "
                                       "to the case)",
                                       name));
    }
    CaseEvidence ce;
    ce.name = name;
    ce.measured = load_measured(spec.settings.data_path, spec);
    ce.spec = std::move(spec);
    if (ce.measured.times.size() < 10 || ce.measured.series.empty())
      throw DiagnosisError(
          fmt::format("case '{}': too few measured samples to diagnose (need at least 10)", name));
    ev_.cases.push_back(std::move(ce));
  }
  if (ev_.cases.empty())
    throw DiagnosisError("no case of the model has measured data; nothing to diagnose (add "
                         "`data \"file.csv\"` to a case)");
  // Baseline simulation and the screen's evidence.
  std::vector<double> sigmas;
  for (auto& ce : ev_.cases) {
    const auto all_nodes = run_case(ce.spec, ce.times());
    ce.simulated.assign(ce.measured.series.size(), {});
    for (std::size_t s = 0; s < ce.measured.series.size(); ++s) {
      for (const auto& row : all_nodes)
        ce.simulated[s].push_back(row[static_cast<std::size_t>(ce.measured.series[s].node_index)]);
      const auto& node = ce.spec.nodes[static_cast<std::size_t>(ce.measured.series[s].node_index)];
      if (!node.boundary) sigmas.push_back(estimate_noise(ce.measured.series[s].values));
    }
    build_screen(ce, all_nodes, ev_.screen_total);
    const auto& t = ce.times();
    split_.push_back(t.front() + (1.0 - opt_.holdout) * (t.back() - t.front()));
  }
  double s2 = 0.0;
  for (double s : sigmas)
    s2 += s * s;
  ev_.noise_floor = sigmas.empty() ? 0.0 : std::sqrt(s2 / static_cast<double>(sigmas.size()));
  for (const auto& ce : ev_.cases)
    baseline_.push_back(ce.simulated);
}

void Engine::build_screen(CaseEvidence& ce, const std::vector<std::vector<double>>& all,
                          double& screen_total) {
  const auto& t = ce.times();
  const std::size_t nk = t.size(), nn = ce.spec.nodes.size();
  constexpr int half = 4;
  ce.T = all;
  ce.dTdt.assign(nk, std::vector<double>(nn, 0.0));
  ce.q.assign(nk, std::vector<double>(nn, std::numeric_limits<double>::quiet_NaN()));
  Network net(ce.spec);
  std::vector<int> unknown_of(nn, -1);
  for (std::size_t u = 0; u < net.unknown_nodes().size(); ++u)
    unknown_of[static_cast<std::size_t>(net.unknown_nodes()[u])] = static_cast<int>(u);
  std::vector<double> sm, sl;
  for (const auto& s : ce.measured.series) {
    const auto i = static_cast<std::size_t>(s.node_index);
    smooth_series(t, s.values, half, sm, sl);
    for (std::size_t k = 0; k < nk; ++k)
      if (std::isfinite(sm[k]) && !ce.spec.nodes[i].boundary) {
        ce.T[k][i] = sm[k];
        ce.dTdt[k][i] = sl[k];
      }
    if (!ce.spec.nodes[i].boundary && ce.spec.nodes[i].C > 0.0 && unknown_of[i] >= 0)
      ce.rows.push_back(s.node_index);
  }
  // Samples whose smoothing window straddles a jump of a source or boundary are left out.
  const std::vector<double> corners = net.breakpoints(t.front(), t.back());
  std::vector<double> Tu(static_cast<std::size_t>(net.size())), F(Tu.size());
  for (std::size_t k = 0; k < nk; ++k) {
    const double ta = t[k >= half ? k - half : 0], tb = t[std::min(nk - 1, k + half)];
    bool straddles = false;
    for (double c : corners)
      if (c > ta && c < tb) straddles = true;
    if (straddles) continue;
    for (std::size_t u = 0; u < Tu.size(); ++u)
      Tu[u] = ce.T[k][static_cast<std::size_t>(net.unknown_nodes()[u])];
    net.heat_balance(t[k], Tu.data(), F.data());
    for (int node : ce.rows) {
      const auto i = static_cast<std::size_t>(node);
      const double C = ce.spec.nodes[i].C;
      const double v = C * ce.dTdt[k][i] - F[static_cast<std::size_t>(unknown_of[i])];
      ce.q[k][i] = std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN();
      if (std::isfinite(v)) screen_total += v * v / (C * C);
    }
  }
}

CaseSims Engine::simulate(const Hypothesis* h, const Candidate* c,
                          const std::vector<double>& p) const {
  CaseSims sims;
  for (std::size_t ci = 0; ci < ev_.cases.size(); ++ci) {
    const CaseEvidence& ce = ev_.cases[ci];
    std::vector<Series> cs;
    if (!h || c->measurement_side) {
      cs = ce.simulated;
    } else {
      const lang::ParamValues ov = h->overrides(*c, p);
      lang::NetworkSpec spec = ov.empty() ? ce.spec : model_.instantiate(ce.name, ov);
      h->extend(*c, p, spec);
      const auto all = run_case(std::move(spec), ce.times());
      cs.assign(ce.measured.series.size(), {});
      for (std::size_t s = 0; s < ce.measured.series.size(); ++s)
        for (const auto& row : all)
          cs[s].push_back(row[static_cast<std::size_t>(ce.measured.series[s].node_index)]);
    }
    if (h)
      for (std::size_t s = 0; s < cs.size(); ++s)
        h->correct(*c, p, ce.measured.series[s].node_index, ce.times(), cs[s]);
    sims.push_back(std::move(cs));
  }
  return sims;
}

bool Engine::in_part(std::size_t c, std::size_t k, Part part) const {
  if (part == Part::all) return true;
  const bool held = ev_.cases[c].times()[k] > split_[c];
  return part == Part::holdout ? held : !held;
}

void Engine::residuals(const CaseSims& sims, Part part, std::vector<double>& r) const {
  r.clear();
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    const auto& m = ev_.cases[c].measured;
    for (std::size_t s = 0; s < m.series.size(); ++s)
      for (std::size_t k = 0; k < m.times.size(); ++k) {
        const double v = m.series[s].values[k];
        if (std::isnan(v) || !in_part(c, k, part)) continue;
        r.push_back(sims[c][s][k] - v);
      }
  }
}

double Engine::sst(Part part) const {
  double sum = 0.0, sum2 = 0.0;
  std::size_t n = 0;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    const auto& m = ev_.cases[c].measured;
    for (const auto& s : m.series)
      for (std::size_t k = 0; k < m.times.size(); ++k)
        if (!std::isnan(s.values[k]) && in_part(c, k, part)) sum += s.values[k], ++n;
  }
  const double mean = n ? sum / static_cast<double>(n) : 0.0;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    const auto& m = ev_.cases[c].measured;
    for (const auto& s : m.series)
      for (std::size_t k = 0; k < m.times.size(); ++k)
        if (!std::isnan(s.values[k]) && in_part(c, k, part))
          sum2 += (s.values[k] - mean) * (s.values[k] - mean);
  }
  return sum2;
}

/// Bounded Levenberg-Marquardt on the candidate's parameters (log scale where positive).
Engine::Fit Engine::fit(const Hypothesis& h, const Candidate& c, std::vector<double> start,
                        Part part, int max_iter, double rtol) const {
  const std::size_t np = start.size();
  auto to_u = [&](const std::vector<double>& p) {
    Eigen::VectorXd u(static_cast<long>(np));
    for (std::size_t j = 0; j < np; ++j)
      u[static_cast<long>(j)] = c.lo[j] > 0 ? std::log(std::clamp(p[j], c.lo[j], c.hi[j]))
                                            : std::clamp(p[j], c.lo[j], c.hi[j]);
    return u;
  };
  auto to_p = [&](const Eigen::VectorXd& u) {
    std::vector<double> p(np);
    for (std::size_t j = 0; j < np; ++j) {
      const double v = c.lo[j] > 0 ? std::exp(u[static_cast<long>(j)]) : u[static_cast<long>(j)];
      p[j] = std::clamp(v, c.lo[j], c.hi[j]);
    }
    return p;
  };
  auto resid = [&](const Eigen::VectorXd& u, Eigen::VectorXd& r) {
    try {
      std::vector<double> rv;
      residuals(simulate(&h, &c, to_p(u)), part, rv);
      r = Eigen::Map<Eigen::VectorXd>(rv.data(), static_cast<long>(rv.size()));
      return r.allFinite();
    } catch (const std::exception&) {
      return false;
    }
  };
  Fit f;
  Eigen::VectorXd u = to_u(start), r;
  if (!resid(u, r)) return f;
  double sse = r.squaredNorm(), lambda = 1e-3;
  Eigen::MatrixXd J(r.size(), static_cast<long>(np));
  for (int it = 0; it < max_iter; ++it) {
    // Forward-difference Jacobian in the scaled coordinates.
    bool okJ = true;
    for (std::size_t j = 0; j < np && okJ; ++j) {
      const long jj = static_cast<long>(j);
      double step = c.lo[j] > 0 ? 1e-3
                                : 1e-3 * std::max(1.0, std::abs(u[jj])) *
                                      std::max(1e-6, (c.hi[j] - c.lo[j]) * 1e-2);
      // At (or near) the upper bound a forward step would be clamped away (a zero column that
      // pins the parameter to the bound): step backwards instead.
      const double u_hi = c.lo[j] > 0 ? std::log(c.hi[j]) : c.hi[j];
      if (u[jj] + step > u_hi) step = -step;
      Eigen::VectorXd u2 = u, r2;
      u2[jj] += step;
      okJ = resid(u2, r2) && r2.size() == r.size();
      if (okJ) J.col(jj) = (r2 - r) / step;
    }
    if (!okJ) break;
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 8 && !improved; ++tries) {
      Eigen::MatrixXd M = A;
      for (long d = 0; d < M.rows(); ++d)
        M(d, d) += lambda * std::max(A(d, d), 1e-12);
      const Eigen::VectorXd du = M.ldlt().solve(-g);
      Eigen::VectorXd un = to_u(to_p(u + du)), rn;
      if (resid(un, rn) && rn.squaredNorm() < sse) {
        const double rel = (sse - rn.squaredNorm()) / std::max(sse, 1e-300);
        u = un, r = rn, sse = rn.squaredNorm();
        lambda = std::max(lambda / 5.0, 1e-9);
        improved = true;
        if (rel < rtol) it = 1 << 20;
      } else {
        lambda *= 8.0;
      }
    }
    if (!improved) break;
  }
  f.ok = true;
  f.p = to_p(u);
  f.sse = sse;
  f.n = static_cast<std::size_t>(r.size());
  // Standard errors from J^T J at the optimum (last Jacobian), mapped back to the parameters.
  f.se.assign(np, std::numeric_limits<double>::quiet_NaN());
  if (f.n > np && J.rows() == r.size()) {
    const Eigen::MatrixXd A = J.transpose() * J;
    Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
    if (lu.isInvertible()) {
      const Eigen::MatrixXd cov = lu.inverse() * (sse / static_cast<double>(f.n - np));
      for (std::size_t j = 0; j < np; ++j) {
        const double su = std::sqrt(std::max(0.0, cov(static_cast<long>(j), static_cast<long>(j))));
        f.se[j] = c.lo[j] > 0 ? f.p[j] * su : su;
      }
    }
  }
  return f;
}

FitMetrics Engine::metrics(const CaseSims& sims) const {
  FitMetrics fm;
  double sse = 0.0;
  std::size_t n = 0;
  std::map<std::string, double> node_sse, node_sum;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    const CaseEvidence& ce = ev_.cases[c];
    const auto& t = ce.times();
    const double dt =
        (t.back() - t.front()) / static_cast<double>(std::max<std::size_t>(1, t.size() - 1));
    for (std::size_t s = 0; s < ce.measured.series.size(); ++s) {
      const auto& meas = ce.measured.series[s].values;
      const auto& sim = sims[c][s];
      NodeMetrics nm;
      double e2 = 0.0, e1 = 0.0;
      for (std::size_t k = 0; k < t.size(); ++k) {
        if (std::isnan(meas[k])) continue;
        const double e = sim[k] - meas[k];
        e2 += e * e, e1 += e, ++nm.points;
        if (std::abs(e) > std::abs(nm.max_error)) nm.max_error = e, nm.max_error_time = t[k];
      }
      nm.max_error_case = ce.name;
      if (nm.points) {
        nm.rmse = std::sqrt(e2 / static_cast<double>(nm.points));
        nm.bias = e1 / static_cast<double>(nm.points);
      }
      // Trend disagreement: slopes of opposite sign, both beyond the noise of a slope estimate.
      std::vector<double> sm, slm, ss, sls;
      smooth_series(t, meas, 4, sm, slm);
      smooth_series(t, sim, 2, ss, sls);
      const double th = 3.0 * ev_.noise_floor * 0.13 / std::max(dt, 1e-9);
      std::size_t k = 0;
      while (k < t.size()) {
        auto bad = [&](std::size_t j) {
          return std::isfinite(slm[j]) && std::isfinite(sls[j]) && std::abs(slm[j]) > th &&
                 std::abs(sls[j]) > th * 0.1 && slm[j] * sls[j] < 0.0;
        };
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
            nm.longest_mismatch_case = ce.name;
            nm.measured_rising = slm[k] > 0.0;
          }
        }
        k = e + 1;
      }
      const std::string& name = ce.measured.series[s].node;
      NodeMetrics& tot = fm.nodes[name];
      node_sse[name] += e2, node_sum[name] += e1;
      tot.points += nm.points;
      if (std::abs(nm.max_error) > std::abs(tot.max_error))
        tot.max_error = nm.max_error, tot.max_error_time = nm.max_error_time,
        tot.max_error_case = ce.name;
      tot.trend_mismatch_s += nm.trend_mismatch_s;
      if (nm.longest_mismatch_s > tot.longest_mismatch_s) {
        tot.longest_mismatch_s = nm.longest_mismatch_s;
        tot.longest_mismatch_start = nm.longest_mismatch_start;
        tot.longest_mismatch_case = nm.longest_mismatch_case;
        tot.measured_rising = nm.measured_rising;
      }
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
  const double total = sst(Part::all);
  fm.r2 = total > 0 ? 1.0 - sse / total : 0.0;
  return fm;
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

Finding Engine::evaluate(const Hypothesis& h, const Candidate& c, bool joint) const {
  Finding f;
  f.candidate = c;
  f.evidence = c.evidence;
  const double nf = static_cast<double>(n_fit_), na = static_cast<double>(n_all_);
  // 1. Fit on the fitting stretch, judge on the held-back stretch.
  // The joint refit (many parameters, started at the recalibrated values) stops earlier.
  const int max_iter = joint ? 12 : 30;
  const double rtol = joint ? 1e-5 : 1e-7;
  Fit a = fit(h, c, c.start, Part::fit, max_iter, rtol);
  if (!a.ok) return f;
  std::vector<double> r;
  CaseSims sa;
  try {
    sa = simulate(&h, &c, a.p);
  } catch (const std::exception&) {
    return f;
  }
  residuals(sa, Part::holdout, r);
  double hold = 0.0;
  for (double x : r)
    hold += x * x;
  // 2. Refit on all data from there: the reported values.
  Fit b = fit(h, c, a.p, Part::all, max_iter, rtol);
  if (!b.ok) return f;
  f.values = b.p;
  f.std_errors = b.se;
  const double k = static_cast<double>(c.start.size());
  f.rmse_before = std::sqrt(sse_base_all_ / na);
  f.rmse_after = std::sqrt(b.sse / na);
  const double total = sst(Part::all), total_hold = sst(Part::holdout);
  f.r2_before = total > 0 ? 1.0 - sse_base_all_ / total : 0.0;
  f.r2_after = total > 0 ? 1.0 - b.sse / total : 0.0;
  f.fit_rmse_before = std::sqrt(sse_base_fit_ / nf);
  f.fit_rmse_after = std::sqrt(a.sse / nf);
  const double nh = std::max(1.0, static_cast<double>(n_hold_));
  f.validation_rmse_before = std::sqrt(sse_base_hold_ / nh);
  f.validation_rmse_after = std::sqrt(hold / nh);
  f.validation_r2_before = total_hold > 0 ? 1.0 - sse_base_hold_ / total_hold : 0.0;
  f.validation_r2_after = total_hold > 0 ? 1.0 - hold / total_hold : 0.0;
  const double floor2 = std::max(ev_.noise_floor * ev_.noise_floor, 1e-12) * 1e-4;
  f.delta_bic =
      na * std::log((b.sse + floor2 * na) / (sse_base_all_ + floor2 * na)) + k * std::log(na);
  f.statement = h.statement(c, b.p, ev_);
  return f;
}

DiagnosisReport Engine::run() {
  const auto t0 = std::chrono::steady_clock::now();
  collect_evidence();
  DiagnosisReport rep;
  rep.model = model_.path();
  for (const auto& ce : ev_.cases)
    rep.cases.push_back(ce.name);
  rep.noise_floor = ev_.noise_floor;
  rep.baseline = metrics(baseline_);
  std::vector<double> r;
  auto sum2 = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v)
      s += x * x;
    return s;
  };
  residuals(baseline_, Part::all, r);
  sse_base_all_ = sum2(r), n_all_ = r.size();
  residuals(baseline_, Part::fit, r);
  sse_base_fit_ = sum2(r), n_fit_ = r.size();
  residuals(baseline_, Part::holdout, r);
  sse_base_hold_ = sum2(r), n_hold_ = r.size();

  // The noise-floor rule: nothing is wrong when every node is within the measurement noise.
  const double nf = ev_.noise_floor;
  double worst = 0.0;
  for (const auto& [name, nm] : rep.baseline.nodes)
    worst = std::max(worst, nm.rmse);
  rep.at_noise_floor = nf > 0 && rep.baseline.rmse <= 1.25 * nf && worst <= 1.6 * nf;

  // Screen: every plugin proposes; model-side candidates are comparable by their screen score.
  struct Entry {
    const Hypothesis* h;
    Candidate c;
  };
  std::vector<std::unique_ptr<Hypothesis>> hyps;
  std::vector<Entry> model_side, chosen;
  for (const auto& name : HypothesisRegistry::global().names()) {
    hyps.push_back(HypothesisRegistry::global().find(name)->create());
    for (auto& c : hyps.back()->propose(ev_)) {
      ++rep.screened;
      if (c.measurement_side || c.kind == "parameter")
        chosen.push_back({hyps.back().get(), std::move(c)});
      else
        model_side.push_back({hyps.back().get(), std::move(c)});
    }
  }
  std::stable_sort(model_side.begin(), model_side.end(),
                   [](const Entry& a, const Entry& b) { return a.c.screen > b.c.screen; });
  std::set<std::string> kinds_taken;
  std::set<std::size_t> picked;
  for (std::size_t i = 0; i < model_side.size(); ++i) {
    const bool top = picked.size() < opt_.refits;
    const bool first_of_kind = kinds_taken.insert(model_side[i].c.kind).second;
    if ((top || first_of_kind) && model_side[i].c.screen > 0) picked.insert(i);
  }
  // Both mechanisms of every picked link, so that the data can tell them apart.
  for (std::size_t i : std::set<std::size_t>(picked))
    if (model_side[i].c.kind == "missing_link")
      for (std::size_t j = 0; j < model_side.size(); ++j)
        if (model_side[j].c.kind == "missing_link" &&
            model_side[j].c.nodes == model_side[i].c.nodes)
          picked.insert(j);
  for (std::size_t i : picked)
    chosen.push_back(model_side[i]);
  rep.refitted = chosen.size();

  std::vector<Finding> results(chosen.size());
  if (!rep.at_noise_floor)
    parallel_for(chosen.size(), opt_.threads,
                 [&](std::size_t i) { results[i] = evaluate(*chosen[i].h, chosen[i].c); });

  // Joint refit: when recalibrating the ranged params alone is significant (the `parameter`
  // candidate beats the baseline by the information criterion), the model's params are wrong too,
  // so a candidate's own parameter fitted at the declared values says little. Every refitted
  // model-side candidate is then refitted again with its parameter and every ranged param together
  // (bounded, started at the recalibrated values) and compared on that footing: the joint result
  // replaces its own-parameter refit, and its extra parameter must also beat the recalibration
  // alone by the BIC margin (otherwise the recalibration explains it: `parameter`).
  std::vector<std::unique_ptr<Joint>> joints;
  std::vector<double> vs_parameter(chosen.size(), -std::numeric_limits<double>::infinity());
  std::size_t ipar = chosen.size();
  for (std::size_t i = 0; i < chosen.size(); ++i)
    if (chosen[i].c.kind == "parameter") ipar = i;
  if (!rep.at_noise_floor && ipar < chosen.size() && !results[ipar].values.empty() &&
      results[ipar].delta_bic < -10.0) {
    // The screen is repeated at the recalibrated params (the unexplained heat flows change with
    // them); its shortlist, picked by the same rule, joins the one from the declared values.
    auto same = [](const Candidate& a, const Candidate& b) {
      return a.kind == b.kind && a.nodes == b.nodes && a.mechanism == b.mechanism &&
             a.element == b.element;
    };
    std::vector<Entry> rescreened;
    try {
      Evidence ev2 = ev_;
      ev2.screen_total = 0.0;
      const lang::ParamValues ov = chosen[ipar].h->overrides(chosen[ipar].c, results[ipar].values);
      for (auto& ce : ev2.cases) {
        ce.spec = model_.instantiate(ce.name, ov);
        const auto all_nodes = run_case(ce.spec, ce.times());
        ce.rows.clear();
        build_screen(ce, all_nodes, ev2.screen_total);
      }
      std::vector<Entry> side;
      for (const auto& hp : hyps)
        for (auto& c : hp->propose(ev2))
          if (!c.measurement_side && c.kind != "parameter") side.push_back({hp.get(), std::move(c)});
      std::stable_sort(side.begin(), side.end(),
                       [](const Entry& a, const Entry& b) { return a.c.screen > b.c.screen; });
      // Twice as many sites as the declared-value shortlist (the screen at wrong params is a weak
      // guide, and the recalibrated one ranks many near-equal sites), counted by site (kind, nodes,
      // element): the two mechanisms of a link are one site.
      std::set<std::string> kinds2, sites2;
      std::set<std::size_t> picked2;
      for (std::size_t i = 0; i < side.size(); ++i) {
        const std::string site = fmt::format("{}|{}|{}", side[i].c.kind,
                                             fmt::join(side[i].c.nodes, ","), side[i].c.element);
        const bool top = sites2.size() < 2 * opt_.refits || sites2.count(site) != 0;
        if (top && side[i].c.screen > 0) sites2.insert(site);
        const bool first_of_kind = kinds2.insert(side[i].c.kind).second;
        if ((top || first_of_kind) && side[i].c.screen > 0) picked2.insert(i);
      }
      for (std::size_t i : std::set<std::size_t>(picked2))
        if (side[i].c.kind == "missing_link")
          for (std::size_t j = 0; j < side.size(); ++j)
            if (side[j].c.kind == "missing_link" && side[j].c.nodes == side[i].c.nodes)
              picked2.insert(j);
      for (std::size_t i : picked2) {
        bool known = false;
        for (const auto& e : chosen)
          known = known || same(e.c, side[i].c);
        if (!known) rescreened.push_back(side[i]);
      }
    } catch (const std::exception&) {
      rescreened.clear(); // the recalibrated screen failed: the declared-value shortlist only
    }
    for (auto& e : rescreened) {
      chosen.push_back(e);
      results.emplace_back(); // no own-parameter refit: evaluated jointly only
      vs_parameter.push_back(-std::numeric_limits<double>::infinity());
    }
    std::vector<std::size_t> todo;
    std::vector<Entry> jentries;
    for (std::size_t i = 0; i < chosen.size(); ++i) {
      if (chosen[i].c.measurement_side || i == ipar) continue;
      joints.push_back(
          std::make_unique<Joint>(chosen[i].h, chosen[i].c, chosen[ipar].h, chosen[ipar].c));
      todo.push_back(i);
      jentries.push_back({joints.back().get(), joints.back()->candidate(results[ipar].values)});
    }
    std::vector<Finding> jres(todo.size());
    parallel_for(todo.size(), opt_.threads,
                 [&](std::size_t j) { jres[j] = evaluate(*jentries[j].h, jentries[j].c, true); });
    rep.refitted += todo.size();
    const double na = static_cast<double>(n_all_);
    const double floor2 = std::max(nf * nf, 1e-12) * 1e-4;
    const double sse_par = results[ipar].rmse_after * results[ipar].rmse_after * na;
    for (std::size_t j = 0; j < todo.size(); ++j) {
      if (jres[j].values.empty()) continue; // the joint fit failed: keep the own-parameter refit
      const std::size_t i = todo[j];
      const double sse = jres[j].rmse_after * jres[j].rmse_after * na;
      const double extra = static_cast<double>(chosen[i].c.start.size());
      vs_parameter[i] =
          na * std::log((sse + floor2 * na) / (sse_par + floor2 * na)) + extra * std::log(na);
      jres[j].evidence += (jres[j].evidence.empty() ? "" : "; ") +
                          fmt::format("refitted jointly with the ranged params ({})",
                                      fmt::join(chosen[ipar].c.names, ", "));
      results[i] = std::move(jres[j]);
      chosen[i] = jentries[j];
    }
  }

  // Significance: better by the information criterion, not worse on held-back data.
  for (std::size_t i = 0; i < results.size(); ++i) {
    Finding& f = results[i];
    if (f.values.empty()) continue;
    f.significant = f.delta_bic < -10.0 &&
                    f.validation_rmse_after <= f.validation_rmse_before + 0.1 * nf &&
                    f.rmse_after < 0.97 * f.rmse_before && vs_parameter[i] < -10.0;
  }
  // Mechanism honesty: merge the two mechanisms of a link.
  for (std::size_t i = 0; i < results.size(); ++i)
    for (std::size_t j = i + 1; j < results.size(); ++j) {
      Finding &a = results[i], &b = results[j];
      if (a.values.empty() || b.values.empty() || a.candidate.kind != "missing_link" ||
          b.candidate.kind != "missing_link" || a.candidate.nodes != b.candidate.nodes)
        continue;
      const double na = static_cast<double>(n_all_);
      const double d = na * std::log((a.rmse_after * a.rmse_after + 1e-300) /
                                     (b.rmse_after * b.rmse_after + 1e-300));
      Finding& keep = d <= 0 ? a : b;
      Finding& drop = d <= 0 ? b : a;
      if (std::abs(d) < 10.0) {
        keep.mechanism_identified = false;
        keep.mechanism_note =
            fmt::format("linear and radiation fit equally (RMSE {:.4g} vs {:.4g} K); kept {}",
                        keep.rmse_after, drop.rmse_after, keep.candidate.mechanism);
      } else {
        keep.mechanism_note = fmt::format("{} fits better than {} (RMSE {:.4g} vs {:.4g} K)",
                                          keep.candidate.mechanism, drop.candidate.mechanism,
                                          keep.rmse_after, drop.rmse_after);
      }
      drop.values.clear(); // merged into keep
    }

  // Rank: BIC on the fitted stretch plus the predictive error on the held-back stretch.
  auto score = [&](const Finding& f) {
    const double nfit = static_cast<double>(n_fit_),
                 nh = std::max(1.0, static_cast<double>(n_hold_));
    const double fit2 = std::max(f.fit_rmse_after * f.fit_rmse_after, 1e-300);
    const double hold2 = std::max(f.validation_rmse_after * f.validation_rmse_after, 1e-300);
    return nfit * std::log(fit2) + static_cast<double>(f.values.size()) * std::log(nfit) +
           nh * std::log(hold2);
  };
  std::vector<Finding> sig, rest;
  for (auto& f : results) {
    if (f.values.empty()) continue;
    (f.significant ? sig : rest).push_back(std::move(f));
  }
  std::stable_sort(sig.begin(), sig.end(),
                   [&](const Finding& a, const Finding& b) { return score(a) < score(b); });
  if (sig.size() > opt_.top) sig.resize(opt_.top);
  for (std::size_t i = 0; i < sig.size(); ++i) {
    sig[i].rank = static_cast<int>(i + 1);
    std::string words = trend_words(rep.baseline, sig[i].candidate.nodes);
    if (!words.empty()) sig[i].evidence += (sig[i].evidence.empty() ? "" : "; ") + words;
  }
  rep.findings = std::move(sig);
  rep.rejected = std::move(rest);

  // Curves for plots: measured, baseline and the best finding.
  CaseSims after;
  if (!rep.findings.empty()) {
    const Finding& best = rep.findings.front();
    for (const auto& e : chosen)
      if (e.c.kind == best.candidate.kind && e.c.nodes == best.candidate.nodes &&
          e.c.mechanism == best.candidate.mechanism && e.c.element == best.candidate.element) {
        try {
          after = simulate(e.h, &e.c, best.values);
        } catch (const std::exception&) {
        }
        break;
      }
  }
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    DiagnosisReport::Curves cv;
    cv.case_name = ev_.cases[c].name;
    cv.times = ev_.cases[c].times();
    for (std::size_t s = 0; s < ev_.cases[c].measured.series.size(); ++s) {
      const std::string& n = ev_.cases[c].measured.series[s].node;
      cv.measured[n] = ev_.cases[c].measured.series[s].values;
      cv.before[n] = baseline_[c][s];
      if (!after.empty()) cv.after[n] = after[c][s];
    }
    rep.curves.push_back(std::move(cv));
  }
  rep.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

} // namespace

DiagnosisReport diagnose(const lang::Model& model, const DiagnosisOptions& options) {
  Engine e(model, options);
  return e.run();
}

} // namespace thermnet
