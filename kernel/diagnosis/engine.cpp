// The diagnosis engine's machinery: evidence (baseline simulation, noise floor, unexplained heat
// flows), simulation of candidates on top of applied findings, residuals per validation fold,
// bounded Levenberg-Marquardt fits (warm-started fold refits), fit metrics and the evaluation of a
// candidate (gain on all data and on held-out data).

#include "kernel/diagnosis/engine.hpp"

#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/elaborator.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermnet::detail {

namespace {

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
  const SolverOptions solver = diagnosis_solver();
  std::vector<double> T = start_state(net, solver);
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

double sum2(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v)
    s += x * x;
  return s;
}

} // namespace

bool same_candidate(const Candidate& a, const Candidate& b) {
  return a.kind == b.kind && a.nodes == b.nodes && a.mechanism == b.mechanism &&
         a.element == b.element;
}

// ------------------------------------------------------------------ composite hypotheses

lang::ParamValues Stack::overrides(const Candidate&, const std::vector<double>& p) const {
  lang::ParamValues v;
  for (const auto& a : *applied_)
    for (auto& [k, x] : a.h->overrides(a.c, a.p))
      v.insert_or_assign(k, x);
  if (free_)
    for (auto& [k, x] : free_->overrides(*fc_, p))
      v.insert_or_assign(k, x);
  return v;
}

void Stack::extend(const Candidate&, const std::vector<double>& p, lang::NetworkSpec& spec) const {
  for (const auto& a : *applied_)
    a.h->extend(a.c, a.p, spec);
  if (free_) free_->extend(*fc_, p, spec);
}

void Stack::correct(const Candidate&, const std::vector<double>& p, int node,
                    const std::vector<double>& times, std::vector<double>& sim) const {
  for (const auto& a : *applied_)
    a.h->correct(a.c, a.p, node, times, sim);
  if (free_) free_->correct(*fc_, p, node, times, sim);
}

std::string Stack::statement(const Candidate&, const std::vector<double>& p,
                             const Evidence& ev) const {
  return free_ ? free_->statement(*fc_, p, ev) : std::string();
}

CaseLines Stack::case_statements(const Candidate&, const std::vector<double>& p,
                                 const Evidence& ev) const {
  return free_ ? free_->case_statements(*fc_, p, ev) : CaseLines();
}

Candidate Compose::candidate() const {
  Candidate c;
  c.measurement_side = true;
  for (const auto& a : parts_) {
    c.kind += (c.kind.empty() ? "" : "+") + a.c.kind;
    c.names.insert(c.names.end(), a.c.names.begin(), a.c.names.end());
    c.start.insert(c.start.end(), a.p.begin(), a.p.end());
    c.lo.insert(c.lo.end(), a.c.lo.begin(), a.c.lo.end());
    c.hi.insert(c.hi.end(), a.c.hi.begin(), a.c.hi.end());
    c.measurement_side = c.measurement_side && a.c.measurement_side;
  }
  return c;
}

std::vector<double> Compose::slice(const std::vector<double>& p, std::size_t i) const {
  std::size_t from = 0;
  for (std::size_t j = 0; j < i; ++j)
    from += parts_[j].c.start.size();
  const auto b = p.begin() + static_cast<long>(from);
  return {b, b + static_cast<long>(parts_[i].c.start.size())};
}

lang::ParamValues Compose::overrides(const Candidate&, const std::vector<double>& p) const {
  lang::ParamValues v;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    for (auto& [k, x] : parts_[i].h->overrides(parts_[i].c, slice(p, i)))
      v.insert_or_assign(k, x);
  return v;
}

void Compose::extend(const Candidate&, const std::vector<double>& p,
                     lang::NetworkSpec& spec) const {
  for (std::size_t i = 0; i < parts_.size(); ++i)
    parts_[i].h->extend(parts_[i].c, slice(p, i), spec);
}

void Compose::correct(const Candidate&, const std::vector<double>& p, int node,
                      const std::vector<double>& times, std::vector<double>& sim) const {
  for (std::size_t i = 0; i < parts_.size(); ++i)
    parts_[i].h->correct(parts_[i].c, slice(p, i), node, times, sim);
}

std::string Compose::statement(const Candidate&, const std::vector<double>& p,
                               const Evidence& ev) const {
  std::string s;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    s.append(i ? "\n" : "").append(parts_[i].h->statement(parts_[i].c, slice(p, i), ev));
  return s;
}

CaseLines Compose::case_statements(const Candidate&, const std::vector<double>& p,
                                   const Evidence& ev) const {
  CaseLines lines;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    merge_case_lines(lines, parts_[i].h->case_statements(parts_[i].c, slice(p, i), ev));
  return lines;
}

Candidate Joint::candidate(const std::vector<double>& ranged) const {
  Candidate c = ic_;
  c.names.insert(c.names.end(), pc_.names.begin(), pc_.names.end());
  c.start.insert(c.start.end(), ranged.begin(), ranged.end());
  c.lo.insert(c.lo.end(), pc_.lo.begin(), pc_.lo.end());
  c.hi.insert(c.hi.end(), pc_.hi.begin(), pc_.hi.end());
  return c;
}

lang::ParamValues Joint::overrides(const Candidate&, const std::vector<double>& p) const {
  lang::ParamValues v = par_->overrides(pc_, tail(p));
  for (auto& [k, x] : inner_->overrides(ic_, head(p)))
    v.insert_or_assign(k, x);
  return v;
}

void Joint::extend(const Candidate&, const std::vector<double>& p, lang::NetworkSpec& spec) const {
  inner_->extend(ic_, head(p), spec);
}

void Joint::correct(const Candidate&, const std::vector<double>& p, int node,
                    const std::vector<double>& times, std::vector<double>& sim) const {
  inner_->correct(ic_, head(p), node, times, sim);
}

std::string Joint::statement(const Candidate&, const std::vector<double>& p,
                             const Evidence& ev) const {
  return inner_->statement(ic_, head(p), ev) + "\n# fitted jointly with the ranged params:\n" +
         par_->statement(pc_, tail(p), ev);
}

CaseLines Joint::case_statements(const Candidate&, const std::vector<double>& p,
                                 const Evidence& ev) const {
  return inner_->case_statements(ic_, head(p), ev);
}

std::vector<double> Joint::head(const std::vector<double>& p) const {
  return {p.begin(), p.begin() + static_cast<long>(ic_.start.size())};
}

std::vector<double> Joint::tail(const std::vector<double>& p) const {
  return {p.begin() + static_cast<long>(ic_.start.size()), p.end()};
}

// ------------------------------------------------------------------ evidence

void Engine::collect_evidence() {
  ev_.model = &model_;
  // What the findings' netlist text is written against: the declarations, and every case block.
  const lang::Reporter fail = [](lang::Diagnostic d) {
    if (d.severity == lang::Severity::error) throw lang::ModelError(std::move(d));
  };
  ev_.declared.spec = lang::Elaborator(model_, fail, nullptr, {}, false).run();
  for (const auto& name : model_.case_names())
    ev_.declared_cases.push_back({name, model_.instantiate(name)});
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
  loco_ = ev_.cases.size() >= 2;
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
}

void Engine::build_screen(CaseEvidence& ce, const std::vector<std::vector<double>>& all,
                          double& screen_total, const std::set<int>& distrusted) const {
  const auto& t = ce.times();
  const std::size_t nk = t.size(), nn = ce.spec.nodes.size();
  constexpr int half = 4;
  ce.T = all;
  ce.dTdt.assign(nk, std::vector<double>(nn, 0.0));
  ce.q.assign(nk, std::vector<double>(nn, std::numeric_limits<double>::quiet_NaN()));
  ce.rows.clear();
  Network net(ce.spec);
  std::vector<int> unknown_of(nn, -1);
  for (std::size_t u = 0; u < net.unknown_nodes().size(); ++u)
    unknown_of[static_cast<std::size_t>(net.unknown_nodes()[u])] = static_cast<int>(u);
  std::vector<double> sm, sl;
  for (const auto& s : ce.measured.series) {
    const auto i = static_cast<std::size_t>(s.node_index);
    // A sensor found faulty (an applied measurement-side finding) is not trusted: its node is
    // screened with its simulated temperature, like an unmeasured one.
    if (distrusted.count(s.node_index) != 0) continue;
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

Base Engine::make_base(std::vector<Applied> applied) const {
  Base b;
  b.applied = std::move(applied);
  for (const auto& ce : ev_.cases)
    b.raw.push_back(ce.simulated);
  if (!b.applied.empty()) {
    const Stack stack(&b.applied, nullptr, nullptr);
    const Candidate none;
    b.raw = model_sims(&stack, &none, {}, Part{}, b);
  }
  b.sims = b.raw;
  if (!b.applied.empty()) {
    const Stack stack(&b.applied, nullptr, nullptr);
    correct(stack, Candidate{}, {}, b.sims);
  }
  std::vector<double> r;
  residuals(b.sims, Part{}, r);
  b.sse_all = sum2(r);
  for (std::size_t f = 0; f < folds(); ++f) {
    residuals(b.sims, Part{Part::test, f}, r);
    b.sse_test += sum2(r);
  }
  b.metrics = metrics(b.sims);
  b.at_floor = at_floor(b.metrics);
  return b;
}

Evidence Engine::evidence_at(const Base& base) const {
  Evidence ev = ev_;
  ev.screen_total = 0.0;
  std::set<int> distrusted;
  for (const auto& a : base.applied)
    if (a.c.measurement_side)
      for (int i : a.c.index)
        distrusted.insert(i);
  const Stack stack(&base.applied, nullptr, nullptr);
  const Candidate none;
  for (std::size_t c = 0; c < ev.cases.size(); ++c) {
    CaseEvidence& ce = ev.cases[c];
    const lang::ParamValues ov = stack.overrides(none, {});
    ce.spec = ov.empty() ? ev_.cases[c].spec : model_.instantiate(ce.name, ov);
    stack.extend(none, {}, ce.spec);
    ce.simulated = base.sims[c];
    build_screen(ce, run_case(ce.spec, ce.times()), ev.screen_total, distrusted);
  }
  return ev;
}

// ------------------------------------------------------------------ simulation and residuals

bool Engine::case_used(std::size_t c, Part part) const {
  if (part.what == Part::all || !loco_) return true;
  return (c == part.fold) == (part.what == Part::test);
}

bool Engine::in_part(std::size_t c, std::size_t k, Part part) const {
  if (part.what == Part::all) return true;
  if (loco_) return case_used(c, part);
  const bool held = ev_.cases[c].times()[k] > split_[c];
  return held == (part.what == Part::test);
}

CaseSims Engine::model_sims(const Hypothesis* h, const Candidate* c, const std::vector<double>& p,
                            Part part, const Base& base) const {
  CaseSims sims;
  for (std::size_t ci = 0; ci < ev_.cases.size(); ++ci) {
    const CaseEvidence& ce = ev_.cases[ci];
    if (!case_used(ci, part)) {
      sims.emplace_back();
    } else if (!h || c->measurement_side) {
      sims.push_back(base.raw[ci]);
    } else {
      const lang::ParamValues ov = h->overrides(*c, p);
      lang::NetworkSpec spec = ov.empty() ? ce.spec : model_.instantiate(ce.name, ov);
      h->extend(*c, p, spec);
      const auto all = run_case(std::move(spec), ce.times());
      std::vector<Series> cs(ce.measured.series.size());
      for (std::size_t s = 0; s < ce.measured.series.size(); ++s)
        for (const auto& row : all)
          cs[s].push_back(row[static_cast<std::size_t>(ce.measured.series[s].node_index)]);
      sims.push_back(std::move(cs));
    }
  }
  return sims;
}

void Engine::correct(const Hypothesis& h, const Candidate& c, const std::vector<double>& p,
                     CaseSims& sims) const {
  for (std::size_t ci = 0; ci < ev_.cases.size(); ++ci)
    for (std::size_t s = 0; s < sims[ci].size(); ++s)
      h.correct(c, p, ev_.cases[ci].measured.series[s].node_index, ev_.cases[ci].times(),
                sims[ci][s]);
}

CaseSims Engine::simulate(const Hypothesis* h, const Candidate* c, const std::vector<double>& p,
                          Part part, const Base& base) const {
  CaseSims sims = model_sims(h, c, p, part, base);
  if (h) correct(*h, *c, p, sims);
  return sims;
}

void Engine::residuals(const CaseSims& sims, Part part, std::vector<double>& r) const {
  r.clear();
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    if (!case_used(c, part)) continue;
    const auto& m = ev_.cases[c].measured;
    for (std::size_t s = 0; s < m.series.size(); ++s)
      for (std::size_t k = 0; k < m.times.size(); ++k) {
        const double v = m.series[s].values[k];
        if (std::isnan(v) || !in_part(c, k, part)) continue;
        r.push_back(sims[c][s][k] - v);
      }
  }
}

std::vector<char> Engine::rows_in(Part part) const {
  std::vector<char> in;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    const auto& m = ev_.cases[c].measured;
    for (const auto& s : m.series)
      for (std::size_t k = 0; k < m.times.size(); ++k)
        if (!std::isnan(s.values[k])) in.push_back(in_part(c, k, part) ? 1 : 0);
  }
  return in;
}

double Engine::sst(Part part) const {
  double sum = 0.0, s2 = 0.0;
  std::size_t n = 0;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c)
    for (const auto& s : ev_.cases[c].measured.series)
      for (std::size_t k = 0; k < s.values.size(); ++k)
        if (!std::isnan(s.values[k]) && in_part(c, k, part)) sum += s.values[k], ++n;
  const double mean = n ? sum / static_cast<double>(n) : 0.0;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c)
    for (const auto& s : ev_.cases[c].measured.series)
      for (std::size_t k = 0; k < s.values.size(); ++k)
        if (!std::isnan(s.values[k]) && in_part(c, k, part))
          s2 += (s.values[k] - mean) * (s.values[k] - mean);
  return s2;
}

// ------------------------------------------------------------------ fitting

/// Bounded Levenberg-Marquardt on the candidate's parameters (log scale where positive). A warm
/// fit (a validation fold's refit) starts at the warm fit's optimum with its Jacobian and
/// residuals restricted to the part's points, so its first step needs no new Jacobian.
Engine::Fit Engine::fit(const Hypothesis& h, const Candidate& c, const std::vector<double>& start,
                        Part part, const Base& base, int max_iter, double rtol,
                        const Fit* warm) const {
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
      residuals(simulate(&h, &c, to_p(u), part, base), part, rv);
      r = Eigen::Map<Eigen::VectorXd>(rv.data(), static_cast<long>(rv.size()));
      return r.allFinite();
    } catch (const std::exception&) {
      return false;
    }
  };
  Fit f;
  Eigen::VectorXd u = to_u(start), r;
  Eigen::MatrixXd J;
  bool have_J = false;
  if (warm && warm->J.rows() == warm->r.size() && warm->J.cols() == static_cast<long>(np)) {
    const std::vector<char> in = rows_in(part);
    long rows = 0;
    for (char x : in)
      rows += x;
    r.resize(rows);
    J.resize(rows, static_cast<long>(np));
    for (long i = 0, j = 0; i < static_cast<long>(in.size()); ++i)
      if (in[static_cast<std::size_t>(i)]) r[j] = warm->r[i], J.row(j++) = warm->J.row(i);
    u = to_u(warm->p);
    have_J = true;
  } else if (!resid(u, r)) {
    return f;
  }
  double sse = r.squaredNorm(), lambda = 1e-3;
  if (!have_J) J = Eigen::MatrixXd::Zero(r.size(), static_cast<long>(np));
  for (int it = 0; it < max_iter; ++it) {
    // Forward-difference Jacobian in the scaled coordinates.
    bool okJ = true;
    for (std::size_t j = 0; j < np && okJ && !have_J; ++j) {
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
    have_J = false;
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
  f.r = r;
  f.J = J;
  // Standard errors from J^T J at the optimum (last Jacobian), mapped back to the parameters.
  f.se.assign(np, std::numeric_limits<double>::quiet_NaN());
  const auto n = static_cast<std::size_t>(r.size());
  if (n > np && J.rows() == r.size()) {
    const Eigen::MatrixXd A = J.transpose() * J;
    Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
    if (lu.isInvertible()) {
      const Eigen::MatrixXd cov = lu.inverse() * (sse / static_cast<double>(n - np));
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
  const double total = sst(Part{});
  fm.r2 = total > 0 ? 1.0 - sse / total : 0.0;
  return fm;
}

bool Engine::at_floor(const FitMetrics& m) const {
  // Nothing is wrong when the whole fit and every node are within the measurement noise.
  const double nf = ev_.noise_floor;
  double worst = 0.0;
  for (const auto& [name, nm] : m.nodes)
    worst = std::max(worst, nm.rmse);
  return nf > 0 && m.rmse <= 1.25 * nf && worst <= 1.6 * nf;
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

Evaluated Engine::evaluate(const Entry& e, const Base& base, bool joint) const {
  Evaluated out;
  Finding& f = out.f;
  f.candidate = e.c;
  f.evidence = e.c.evidence;
  f.given = static_cast<int>(base.applied.size());
  const Stack stack(&base.applied, e.h, &e.c);
  const Hypothesis& h = base.applied.empty() ? *e.h : stack;
  // The joint refit (many parameters, started at the recalibrated values) stops earlier; a fold's
  // refit starts at the all-data optimum (one step for a joint refit).
  const int max_iter = joint ? 12 : 30, fold_iter = joint ? 1 : 3;
  const double rtol = joint ? 1e-5 : 1e-7;
  // 1. Fit on all data: the reported values.
  const Fit b = fit(h, e.c, e.c.start, Part{}, base, max_iter, rtol);
  if (!b.ok) return out;
  // 2. Validation: refit without each fold's held-out points, score on them.
  std::vector<double> r;
  for (std::size_t k = 0; k < folds(); ++k) {
    const Fit a = fit(h, e.c, b.p, Part{Part::train, k}, base, fold_iter, rtol, &b);
    if (!a.ok) return out;
    try {
      residuals(simulate(&h, &e.c, a.p, Part{Part::test, k}, base), Part{Part::test, k}, r);
    } catch (const std::exception&) {
      return out;
    }
    out.holdout_sse += sum2(r);
  }
  // Residuals per series (the all-data rows, in order) for the mechanism comparison.
  long row = 0;
  for (const auto& ce : ev_.cases)
    for (const auto& s : ce.measured.series) {
      out.r.emplace_back();
      for (double v : s.values)
        if (!std::isnan(v)) out.r.back().push_back(b.r[row++]);
    }
  const double na = static_cast<double>(n_all_), nt = std::max(1.0, static_cast<double>(n_test_));
  const double k = static_cast<double>(e.c.start.size());
  f.values = b.p;
  f.std_errors = b.se;
  f.rmse_before = std::sqrt(base.sse_all / na);
  f.rmse_after = std::sqrt(b.sse / na);
  const double total = sst(Part{});
  double total_test = 0.0;
  for (std::size_t j = 0; j < folds(); ++j)
    total_test += sst(Part{Part::test, j});
  f.r2_before = total > 0 ? 1.0 - base.sse_all / total : 0.0;
  f.r2_after = total > 0 ? 1.0 - b.sse / total : 0.0;
  f.validation_rmse_before = std::sqrt(base.sse_test / nt);
  f.validation_rmse_after = std::sqrt(out.holdout_sse / nt);
  f.validation_r2_before = total_test > 0 ? 1.0 - base.sse_test / total_test : 0.0;
  f.validation_r2_after = total_test > 0 ? 1.0 - out.holdout_sse / total_test : 0.0;
  const double floor2 = std::max(ev_.noise_floor * ev_.noise_floor, 1e-12) * 1e-4;
  f.delta_bic =
      na * std::log((b.sse + floor2 * na) / (base.sse_all + floor2 * na)) + k * std::log(na);
  f.statement = e.h->statement(e.c, b.p, ev_);
  f.case_statements = e.h->case_statements(e.c, b.p, ev_);
  return out;
}

} // namespace thermnet::detail
