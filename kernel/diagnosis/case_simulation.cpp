// The diagnosis's simulations: a case at the measured times, candidates on top of a base, residuals
// and variances over the points of a validation part.

#include "kernel/diagnosis/engine.hpp"

#include "kernel/core/case_sensitivities.hpp"
#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace thermnet::detail {

namespace {

/// Largest network simulated with dense LU; measured crossover (S02/S08, 30-48 nodes: dense as
/// fast; S19-S21/D05, 100-150 nodes: KLU 1.3-2x faster per simulation).
constexpr int kDiagnosisDenseThreshold = 64;

SolverOptions diagnosis_solver() {
  SolverOptions s;
  s.rtol = 1e-7;
  s.atol = 1e-7;
  // A candidate's network is sparse (a handful of links per node): above this size sparse LU (KLU)
  // factors and solves faster than dense LU, which took 65 % of a 150-node diagnosis's CPU time.
  s.dense_threshold = kDiagnosisDenseThreshold;
  // A linear network with tabulated inputs (a building and its weather) is solved exactly from
  // sample to sample instead of restarting BDF at every row of its tables.
  s.exact_linear_max = kDiagnosisDenseThreshold;
  return s;
}

/// How far parameter j is moved to elaborate the network at a moved value (a derivative taken
/// from the elaboration, no simulation): 1e-7 of its size, backwards where that would pass the
/// upper bound.
double moved_step(const Candidate& c, const std::vector<double>& p, std::size_t j) {
  const double h = 1e-7 * parameter_size(c, p, j);
  return p[j] + h > c.hi[j] ? -h : h;
}

/// Largest |value| of simulated series.
double peak(const CaseSims& sims) {
  double m = 0.0;
  for (const auto& c : sims)
    for (const auto& s : c)
      for (double v : s)
        m = std::max(m, std::abs(v));
  return m;
}

} // namespace

double parameter_size(const Candidate& c, const std::vector<double>& p, std::size_t j) {
  const double size = std::max(std::abs(p[j]), 1e-3 * std::abs(c.hi[j] - c.lo[j]));
  return size > 0.0 && std::isfinite(size) ? size : 1.0;
}

namespace {

/// Integrates a case to the measured times: every node's temperature into `nodes` and the
/// series' simulated values into `series`, each when given.
void run_case(lang::NetworkSpec spec, const std::vector<double>& times,
              const MeasuredData* measured, std::vector<Series>* series, RowMatrix* nodes) {
  if (times.empty()) return;
  Network net(std::move(spec));
  if (nodes) nodes->reserve(times.size(), net.spec().nodes.size());
  const SolverOptions solver = diagnosis_solver();
  std::vector<double> T = start_state(net, solver);
  std::vector<double> all(net.spec().nodes.size());
  if (series) {
    series->assign(measured->series.size(), {});
    for (Series& s : *series)
      s.reserve(times.size());
  }
  std::size_t outputs = 0;
  integrate(
      net, T, 0.0, times.back(), times,
      [&](double t, const std::vector<double>& x) {
        net.expand(t, x.data(), all.data());
        if (series)
          for (std::size_t s = 0; s < measured->series.size(); ++s)
            (*series)[s].push_back(
                simulated_value(net, measured->series[s], t, x.data(), all.data()));
        if (nodes) nodes->push_back(all);
        ++outputs;
      },
      solver);
  if (outputs != times.size())
    throw std::runtime_error(
        fmt::format("the simulation gave {} of the {} measured times", outputs, times.size()));
}

} // namespace

/// Simulates a case at the measured times: temperatures of every node (spec order), K.
RowMatrix simulate_case(lang::NetworkSpec spec, const std::vector<double>& times,
                        const MeasuredData* measured, std::vector<Series>* series) {
  RowMatrix out;
  run_case(std::move(spec), times, measured, series, &out);
  return out;
}

std::vector<Series> simulate_series(lang::NetworkSpec spec, const MeasuredData& measured) {
  std::vector<Series> out;
  run_case(std::move(spec), measured.times, &measured, &out, nullptr);
  return out;
}

void Engine::make_folds() {
  // Each case is held out whole, unless a fit to the other cases cannot test what happens in it:
  // with one case, or when it holds an event (--events) no other case holds, its time span is cut
  // into equal stretches, each held out in turn (the other cases and stretches fitted).
  std::vector<char> split(ev_.cases.size(), ev_.cases.size() < 2);
  for (const std::string& name : event_names(ev_.events)) {
    std::vector<std::size_t> with;
    for (std::size_t c = 0; c < ev_.cases.size(); ++c)
      if (std::any_of(ev_.events.begin(), ev_.events.end(), [&](const EventWindow& w) {
            return w.event == name && (w.case_name.empty() || w.case_name == ev_.cases[c].name);
          }))
        with.push_back(c);
    if (with.size() == 1) split[with.front()] = 1;
  }
  // The cases held out whole: each alone, or with more than case_folds of them, in case_folds
  // groups (case i of them with every case_folds-th after it, so that neighbours in the model's
  // order, often similar runs, fall in different folds). Leaving one case out costs a fit to n - 1
  // cases per case, growing with the square of a campaign's cases; 5 folds of 11 cases cut the
  // camera study's diagnosis by a quarter with the same findings (docs/diagnose.md).
  std::size_t whole = 0;
  for (char x : split)
    whole += x ? 0 : 1;
  const std::size_t groups = std::min(whole, std::max<std::size_t>(2, opt_.case_folds));
  folds_.clear();
  group_.assign(ev_.cases.size(), std::numeric_limits<std::size_t>::max());
  std::vector<std::size_t> group_fold(groups, std::numeric_limits<std::size_t>::max());
  const int stretches = static_cast<int>(std::max<std::size_t>(1, opt_.time_folds));
  for (std::size_t c = 0, i = 0; c < ev_.cases.size(); ++c) {
    if (split[c]) {
      for (int s = 0; s < stretches; ++s)
        folds_.push_back({c, s});
      continue;
    }
    std::size_t& f = group_fold[i++ % groups];
    if (f == std::numeric_limits<std::size_t>::max()) {
      f = folds_.size();
      folds_.push_back({c, -1});
    }
    group_[c] = f;
  }
  index_parts();
}

std::string Engine::validation() const {
  const bool any_split =
      std::any_of(folds_.begin(), folds_.end(), [](const Fold& f) { return f.stretch >= 0; });
  if (!any_split) return case_folds().empty() ? "leave_one_case_out" : "case_folds";
  return ev_.cases.size() == 1 ? "held_back_time" : "cases_and_time";
}

std::vector<std::vector<std::string>> Engine::case_folds() const {
  std::vector<std::vector<std::string>> out(folds_.size());
  bool grouped = false;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c)
    if (group_[c] < folds_.size()) {
      out[group_[c]].push_back(ev_.cases[c].name);
      grouped = grouped || out[group_[c]].size() > 1;
    }
  if (!grouped) return {};
  std::erase_if(out, [](const auto& names) { return names.empty(); });
  return out;
}

std::vector<std::string> Engine::split_cases() const {
  std::vector<std::string> out;
  if (ev_.cases.size() < 2) return out;
  for (const Fold& f : folds_)
    if (f.stretch == 0) out.push_back(ev_.cases[f.c].name);
  return out;
}

std::size_t Engine::stretch_of(std::size_t c, std::size_t k) const {
  // The case's time span in time_folds equal stretches.
  const std::size_t n = std::max<std::size_t>(1, opt_.time_folds);
  const auto [t0, span] = span_[c];
  const double x = span > 0 ? (ev_.cases[c].times()[k] - t0) / span : 0.0;
  return std::min(n - 1, static_cast<std::size_t>(std::max(0.0, x * static_cast<double>(n))));
}

bool Engine::case_used(std::size_t c, Part part) const {
  if (part.what == Part::all) return true;
  const Fold& f = folds_[part.fold];
  if (f.stretch >= 0) return part.what == Part::train || c == f.c; // trains on its other stretches
  return (group_[c] == part.fold) == (part.what == Part::test);
}

bool Engine::in_part(std::size_t c, std::size_t k, Part part) const {
  if (part.what == Part::all) return true;
  const Fold& f = folds_[part.fold];
  const bool held = f.stretch < 0
                        ? group_[c] == part.fold
                        : c == f.c && stretch_of(c, k) == static_cast<std::size_t>(f.stretch);
  return held == (part.what == Part::test);
}

CaseSims Engine::model_sims(const Hypothesis* h, const Candidate* c, const std::vector<double>& p,
                            Part part, const Base& base) const {
  CaseSims sims;
  for (std::size_t ci = 0; ci < ev_.cases.size(); ++ci) {
    const CaseEvidence& ce = ev_.cases[ci];
    if (!case_used(ci, part)) {
      sims.emplace_back();
    } else if (!h || (c->measurement_side && !h->recalibrates())) {
      // (a measurement-side candidate refitted with the ranged params needs a new simulation)
      sims.push_back(base.raw[ci]);
    } else {
      const lang::ParamValues ov = h->overrides(*c, p);
      lang::NetworkSpec spec = ov.empty() ? ce.spec : model_.instantiate(ce.name, ov);
      h->extend(*c, p, spec);
      sims.push_back(simulate_series(std::move(spec), ce.measured));
      simulations_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  return sims;
}

/// model_sims() with dsims[j], the derivative of every simulated series by parameter j (zeros where
/// a case does not depend on it), by the cases' forward sensitivities: each parameter moved alone
/// through the hypothesis (overrides, extend) and the model's elaboration gives what it moves in
/// the network. False when a case's network cannot integrate sensitivities.
bool Engine::model_sensitivities(const Hypothesis& h, const Candidate& c,
                                 const std::vector<double>& p, Part part, const Base& base,
                                 CaseSims& sims, std::vector<CaseSims>& dsims) const {
  const std::size_t np = p.size();
  // A series read through a sensor element (its lag, offset and gain) is not a node's
  // temperature: such data take the forward differences of simulations.
  for (const CaseEvidence& ce : ev_.cases)
    for (const auto& s : ce.measured.series)
      if (s.sensor >= 0) return false;
  sims.clear();
  dsims.assign(np, CaseSims{});
  for (std::size_t ci = 0; ci < ev_.cases.size(); ++ci) {
    const CaseEvidence& ce = ev_.cases[ci];
    const std::size_t nseries = ce.measured.series.size();
    if (!case_used(ci, part)) {
      sims.emplace_back();
      for (auto& d : dsims)
        d.emplace_back();
      continue;
    }
    if (c.measurement_side && !h.recalibrates()) { // corrections only: no new simulation
      sims.push_back(base.raw[ci]);
      for (auto& d : dsims)
        d.emplace_back(nseries, Series(ce.times().size(), 0.0));
      continue;
    }
    const lang::ParamValues ov = h.overrides(c, p);
    // (each moved network is elaborated from this one's record: only what its param reaches)
    std::shared_ptr<const lang::ElaborationRecord> record;
    const lang::NetworkSpec inst =
        ov.empty() ? ce.spec : model_.instantiate_recorded(ce.name, ov, record);
    lang::NetworkSpec spec = inst;
    h.extend(c, p, spec);
    std::vector<MovedSpec> moved(np);
    for (std::size_t j = 0; j < np; ++j) {
      std::vector<double> q = p;
      moved[j].step = moved_step(c, p, j);
      moved[j].scale = parameter_size(c, p, j);
      q[j] += moved[j].step;
      const lang::ParamValues ovj = h.overrides(c, q);
      moved[j].spec = ovj == ov ? inst
                      : record  ? model_.instantiate_near(*record, ovj)
                                : model_.instantiate(ce.name, ovj);
      h.extend(c, q, moved[j].spec);
    }
    std::vector<int> nodes;
    for (const auto& s : ce.measured.series)
      nodes.push_back(s.node_index);
    std::string why;
    auto run = simulate_sensitivities(std::move(spec), std::move(moved), ce.times(), nodes,
                                      diagnosis_solver(), &why);
    if (!run) return false;
    simulations_.fetch_add(1, std::memory_order_relaxed);
    sensitivity_runs_.fetch_add(1, std::memory_order_relaxed);
    const std::size_t nt = ce.times().size();
    std::vector<Series> cs(nseries, Series(nt));
    for (std::size_t k = 0; k < nt; ++k)
      for (std::size_t s = 0; s < nseries; ++s)
        cs[s][k] = run->T[k][s];
    sims.push_back(std::move(cs));
    for (std::size_t j = 0; j < np; ++j) {
      std::vector<Series> ds(nseries, Series(nt));
      for (std::size_t k = 0; k < nt; ++k)
        for (std::size_t s = 0; s < nseries; ++s)
          ds[s][k] = run->dT[j][k][s];
      dsims[j].push_back(std::move(ds));
    }
  }
  return true;
}

/// The residuals at p and their Jacobian dr/dp: the simulated series' derivatives (forward
/// sensitivities) carried through the measurement-side corrections, plus the corrections' own
/// derivatives. Both are differences of corrections of series, no simulation: along a series'
/// derivative scaled to move it by at most 1 mK (exact for the corrections in use, which are
/// linear in the series), and along each parameter moved as for the elaboration.
bool Engine::jacobian_residuals(const Hypothesis& h, const Candidate& c,
                                const std::vector<double>& p, Part part, const Base& base,
                                std::vector<double>& r, Eigen::MatrixXd& J) const {
  CaseSims raw;
  std::vector<CaseSims> draw;
  if (!model_sensitivities(h, c, p, part, base, raw, draw)) return false;
  // Where nothing corrects the series, the residuals and their derivatives are the series' own.
  const bool corrects = h.corrects(c);
  CaseSims sims;
  if (corrects) {
    sims = raw;
    correct(h, c, p, sims);
  }
  residuals(corrects ? sims : raw, part, r);
  J.resize(static_cast<long>(r.size()), static_cast<long>(p.size()));
  std::vector<double> col;
  if (!corrects) {
    for (std::size_t j = 0; j < p.size(); ++j) {
      part_values(draw[j], part, col);
      J.col(static_cast<long>(j)) =
          Eigen::Map<const Eigen::VectorXd>(col.data(), static_cast<long>(col.size()));
    }
    return true;
  }
  const auto add_difference = [&](const CaseSims& moved, double by, std::vector<double>& into) {
    residuals(moved, part, col);
    for (std::size_t i = 0; i < col.size(); ++i)
      into[i] += (col[i] - r[i]) / by;
  };
  for (std::size_t j = 0; j < p.size(); ++j) {
    std::vector<double> dj(r.size(), 0.0);
    if (const double m = peak(draw[j]); m > 0.0) {
      const double eps = 1e-3 / m;
      CaseSims moved = raw;
      for (std::size_t ci = 0; ci < moved.size(); ++ci)
        for (std::size_t s = 0; s < moved[ci].size(); ++s)
          for (std::size_t k = 0; k < moved[ci][s].size(); ++k)
            moved[ci][s][k] += eps * draw[j][ci][s][k];
      correct(h, c, p, moved);
      add_difference(moved, eps, dj);
    }
    std::vector<double> q = p;
    const double step = moved_step(c, p, j);
    q[j] += step;
    CaseSims own = raw;
    correct(h, c, q, own);
    add_difference(own, step, dj);
    J.col(static_cast<long>(j)) =
        Eigen::Map<const Eigen::VectorXd>(dj.data(), static_cast<long>(dj.size()));
  }
  return true;
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
  gather(sims, part, true, r);
}

void Engine::part_values(const CaseSims& sims, Part part, std::vector<double>& out) const {
  gather(sims, part, false, out);
}

void Engine::gather(const CaseSims& sims, Part part, bool minus_measured,
                    std::vector<double>& out) const {
  const PartRows& rows = part_rows(part);
  out.clear();
  out.reserve(rows.count);
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    if (!case_used(c, part)) continue;
    const auto& m = ev_.cases[c].measured;
    std::size_t row = case_row_[c];
    for (std::size_t s = 0; s < m.series.size(); ++s) {
      const std::vector<double>& values = m.series[s].values;
      const std::vector<double>& sim = sims[c][s];
      for (std::size_t k = 0; k < values.size(); ++k) {
        const double v = values[k];
        if (std::isnan(v) || !rows.in[row++]) continue;
        out.push_back(minus_measured ? sim[k] - v : sim[k]);
      }
    }
  }
}

bool Engine::covers(const CaseSims& sims, Part part) const {
  if (sims.size() != ev_.cases.size()) return false;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c)
    if (case_used(c, part) && sims[c].size() != ev_.cases[c].measured.series.size()) return false;
  return true;
}

void Engine::index_parts() {
  case_row_.clear();
  std::size_t rows = 0;
  for (const auto& ce : ev_.cases) {
    case_row_.push_back(rows);
    for (const auto& s : ce.measured.series)
      rows += static_cast<std::size_t>(
          std::count_if(s.values.begin(), s.values.end(), [](double v) { return !std::isnan(v); }));
  }
  case_row_.push_back(rows);
  const auto index = [&](Part part) {
    PartRows p;
    p.in.reserve(rows);
    // Summed about the part's first value: data that do not vary give exactly 0 (R² undefined),
    // not the round-off of their mean.
    double first = 0.0, sum = 0.0;
    for (std::size_t c = 0; c < ev_.cases.size(); ++c)
      for (const auto& s : ev_.cases[c].measured.series)
        for (std::size_t k = 0; k < s.values.size(); ++k) {
          if (std::isnan(s.values[k])) continue;
          const bool in = in_part(c, k, part);
          p.in.push_back(in ? 1 : 0);
          if (!in) continue;
          if (p.count++ == 0) first = s.values[k];
          sum += s.values[k] - first;
        }
    const double mean = first + (p.count ? sum / static_cast<double>(p.count) : 0.0);
    std::size_t row = 0;
    for (const auto& ce : ev_.cases)
      for (const auto& s : ce.measured.series)
        for (double v : s.values)
          if (!std::isnan(v) && p.in[row++]) p.sst += (v - mean) * (v - mean);
    return p;
  };
  all_rows_ = index(Part{});
  test_rows_.clear();
  train_rows_.clear();
  n_test_ = 0;
  segments_.clear();
  fold_points_.clear();
  for (std::size_t f = 0; f < folds_.size(); ++f) {
    test_rows_.push_back(index(Part{Part::test, f}));
    train_rows_.push_back(index(Part{Part::train, f}));
    n_test_ += test_rows_.back().count;
    fold_points_.push_back(test_rows_.back().count);
    // the fold's held-out points per series, in the order residuals() lists them
    const std::vector<char>& held = test_rows_.back().in;
    for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
      if (!case_used(c, Part{Part::test, f})) continue;
      std::size_t row = case_row_[c];
      for (const auto& se : ev_.cases[c].measured.series) {
        std::size_t run = 0;
        for (double v : se.values)
          if (!std::isnan(v) && held[row++]) ++run;
        if (run) segments_.push_back(run);
      }
    }
  }
}

const Engine::PartRows& Engine::part_rows(Part part) const {
  if (part.what == Part::all) return all_rows_;
  return part.what == Part::test ? test_rows_.at(part.fold) : train_rows_.at(part.fold);
}

const std::vector<char>& Engine::rows_in(Part part) const {
  return part_rows(part).in;
}

double Engine::sst(Part part) const {
  return part_rows(part).sst;
}

} // namespace thermnet::detail
