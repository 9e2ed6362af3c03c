// The diagnosis's simulations: a case at the measured times, candidates on top of a base, residuals
// and variances over the points of a validation part.

#include "kernel/diagnosis/engine.hpp"

#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"

#include <fmt/format.h>

#include <cmath>
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
  return s;
}

} // namespace

/// Simulates a case at the measured times: temperatures of every node (spec order), K.
std::vector<std::vector<double>> simulate_case(lang::NetworkSpec spec,
                                               const std::vector<double>& times,
                                               const MeasuredData* measured,
                                               std::vector<Series>* series) {
  std::vector<std::vector<double>> out;
  if (times.empty()) return out;
  Network net(std::move(spec));
  const SolverOptions solver = diagnosis_solver();
  std::vector<double> T = start_state(net, solver);
  std::vector<double> all(net.spec().nodes.size());
  if (series) series->assign(measured->series.size(), {});
  integrate(
      net, T, 0.0, times.back(), times,
      [&](double t, const std::vector<double>& x) {
        net.expand(t, x.data(), all.data());
        if (series)
          for (std::size_t s = 0; s < measured->series.size(); ++s)
            (*series)[s].push_back(
                simulated_value(net, measured->series[s], t, x.data(), all.data()));
        out.push_back(all);
      },
      solver);
  if (out.size() != times.size())
    throw std::runtime_error(
        fmt::format("the simulation gave {} of the {} measured times", out.size(), times.size()));
  return out;
}

bool Engine::case_used(std::size_t c, Part part) const {
  if (part.what == Part::all || !loco_) return true;
  return (c == part.fold) == (part.what == Part::test);
}

bool Engine::in_part(std::size_t c, std::size_t k, Part part) const {
  if (part.what == Part::all) return true;
  if (loco_) return case_used(c, part);
  // One case: its time span in folds() equal stretches, the fold's stretch held back.
  const auto [t0, span] = span_[c];
  const double x = span > 0 ? (ev_.cases[c].times()[k] - t0) / span : 0.0;
  const auto stretch = std::min(
      folds() - 1, static_cast<std::size_t>(std::max(0.0, x * static_cast<double>(folds()))));
  return (stretch == part.fold) == (part.what == Part::test);
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
      std::vector<Series> cs;
      simulate_case(std::move(spec), ce.times(), &ce.measured, &cs);
      simulations_.fetch_add(1, std::memory_order_relaxed);
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

} // namespace thermnet::detail
