#include "app/design_search.hpp"

#include "kernel/core/parallel.hpp"
#include "plugins/optimizer/pagmo_sga.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>

namespace thermnet::app {

using lang::RequirementKind;

namespace {

constexpr double penalty_weight = 100.0;
constexpr double failed_fitness = 1e30;

/// The safety margin the search keeps from each limit (so the written model, whose values are
/// rounded, still meets it) and the scale of a violation, in SI.
std::pair<double, double> tolerance_and_scale(const lang::RequirementSpec& r) {
  switch (r.kind) {
  case RequirementKind::band:
  case RequirementKind::gradient:
    return {0.02, 1.0}; // K
  case RequirementKind::power:
  case RequirementKind::energy:
    return {1e-3 * r.hi, std::max(r.hi, 1e-12)};
  case RequirementKind::margin:
    return {0.005, 0.1};
  }
  return {0.0, 1.0};
}

/// A point is better when it is ok, then feasible, then has less violation, then less objective.
bool better(const DesignPoint& a, const DesignPoint& b) {
  if (a.ok != b.ok) return a.ok;
  if (a.violation != b.violation) return a.violation < b.violation;
  return a.objective < b.objective;
}

/// The search's problem over the unit box: penalised objective.
struct PenaltyProblem {
  struct State {
    const DesignProblem* problem = nullptr;
    double scale = 1.0; // objective at the start point
    std::size_t evaluations = 0, failed = 0;
    DesignPoint best;
    const std::atomic<bool>* cancel = nullptr;
  };
  std::shared_ptr<State> state;

  std::vector<double> to_x(const std::vector<double>& u) const {
    const auto& ps = state->problem->params();
    std::vector<double> x(u.size());
    for (std::size_t j = 0; j < u.size(); ++j)
      x[j] = *ps[j].lo + (*ps[j].hi - *ps[j].lo) * std::clamp(u[j], 0.0, 1.0);
    return x;
  }
  double fitness(const std::vector<double>& u) const {
    if (state->cancel && state->cancel->load()) return failed_fitness;
    DesignPoint p = state->problem->evaluate(to_x(u));
    ++state->evaluations;
    if (!p.ok) ++state->failed;
    const double f =
        p.ok ? p.objective / state->scale + penalty_weight * p.violation : failed_fitness;
    if (better(p, state->best)) state->best = std::move(p);
    return f;
  }
};

std::vector<double> to_unit(const DesignProblem& problem, const std::vector<double>& x) {
  std::vector<double> u(x.size());
  for (std::size_t j = 0; j < x.size(); ++j) {
    const auto& p = problem.params()[j];
    const double w = *p.hi - *p.lo;
    u[j] = w > 0 ? (x[j] - *p.lo) / w : 0.0;
  }
  return u;
}

} // namespace

DesignProblem::DesignProblem(const lang::Model& model, std::vector<lang::ParamInfo> params,
                             std::vector<std::string> cases, DesignObjective objective,
                             SimulationOptions options)
    : model_(model), params_(std::move(params)), cases_(std::move(cases)), objective_(objective),
      options_(std::move(options)) {}

lang::ParamValues DesignProblem::values(const std::vector<double>& x) const {
  lang::ParamValues v;
  for (std::size_t j = 0; j < params_.size(); ++j)
    v[params_[j].name] = x[j];
  return v;
}

std::vector<CheckedRun> DesignProblem::run(const std::vector<double>& x,
                                           const std::vector<std::string>& keep) const {
  std::vector<CheckedRun> runs;
  const lang::ParamValues v = values(x);
  for (const auto& c : cases_)
    runs.push_back(run_checked(model_, c, v, options_, keep));
  return runs;
}

DesignPoint DesignProblem::score(const std::vector<double>& x,
                                 const std::vector<CheckedRun>& runs) const {
  DesignPoint p;
  p.x = x;
  p.ok = true;
  p.feasible = true;
  for (const auto& r : runs) {
    const auto& spec = r.net->spec();
    double installed = 0.0;
    for (std::size_t e = 0; e < spec.elements.size(); ++e) {
      const auto& el = spec.elements[e];
      if (el.nodes().size() != 1 || el.composite() != lang::Composite::none) continue;
      if (objective_ == DesignObjective::energy && e < r.energy.element_energy.size())
        p.objective += r.energy.element_energy[e][0];
      if (el.has("P") && el.values.at("P").is_constant()) installed += el.number("P");
    }
    if (objective_ == DesignObjective::power) p.objective = std::max(p.objective, installed);
    for (const auto& o : r.outcomes) {
      p.feasible = p.feasible && o.met;
      const auto [tol, scale] = tolerance_and_scale(*o.req);
      if (!std::isfinite(o.slack)) {
        if (o.slack < 0) p.violation += 1e3;
        continue;
      }
      p.violation += std::max(0.0, tol - o.slack) / scale;
    }
  }
  return p;
}

DesignPoint DesignProblem::evaluate(const std::vector<double>& x) const {
  try {
    return score(x, run(x));
  } catch (const std::exception& e) {
    DesignPoint p;
    p.x = x;
    p.failure = e.what();
    return p;
  }
}

DesignResult design_search(const DesignProblem& problem, const DesignSettings& settings) {
  const std::size_t n = problem.params().size();
  std::vector<double> start(n);
  for (std::size_t j = 0; j < n; ++j)
    start[j] = problem.params()[j].value;
  // Stage 1: the declared values, the upper ends of the ranges (most heating: often feasible,
  // a good start to descend from) and seeded uniform samples, evaluated in parallel by index.
  std::vector<double> upper(n);
  for (std::size_t j = 0; j < n; ++j)
    upper[j] = *problem.params()[j].hi;
  std::vector<std::vector<double>> xs{start, upper};
  for (std::size_t k = 0; k < settings.samples; ++k) {
    std::vector<double> x(n);
    for (std::size_t j = 0; j < n; ++j) {
      const auto& p = problem.params()[j];
      x[j] = *p.lo + (*p.hi - *p.lo) * uniform01(settings.seed, j, k);
    }
    xs.push_back(std::move(x));
  }
  std::vector<DesignPoint> points(xs.size());
  parallel_for(
      xs.size(), settings.threads, [&](std::size_t k) { points[k] = problem.evaluate(xs[k]); },
      settings.cancel);
  auto state = std::make_shared<PenaltyProblem::State>();
  state->problem = &problem;
  state->cancel = settings.cancel;
  state->evaluations = xs.size();
  for (const auto& p : points) {
    if (!p.ok) ++state->failed;
    if (state->best.x.empty() || better(p, state->best)) state->best = p;
  }
  const DesignPoint& first = points.front();
  state->scale = first.ok && first.objective > 0 ? first.objective : 1.0;
  DesignResult result;
  if (state->best.ok && settings.evaluations > 0 && !(settings.cancel && settings.cancel->load())) {
    // Stage 2: compass search from the best point so far (its steps start at a tenth of each
    // range and halve down to a thousandth).
    const PenaltyProblem penalised{state};
    CompassRequest request;
    request.start = to_unit(problem, state->best.x);
    request.max_evaluations = static_cast<unsigned>(settings.evaluations);
    request.fitness = [&penalised](const std::vector<double>& u) { return penalised.fitness(u); };
    load_pagmo_compass()(request);
  }
  result.best = state->best;
  result.evaluations = state->evaluations;
  result.failed = state->failed;
  return result;
}

} // namespace thermnet::app
