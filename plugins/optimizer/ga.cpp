// Optimizer plugin 'ga': pagmo2's simple genetic algorithm (pagmo::sga) on the calibration
// problem. pagmo itself is reached through libthermnet_pagmo_sga, loaded the first time 'ga' runs
// (plugins/optimizer/pagmo_sga.hpp, plugins/pagmo_sga/pagmo_sga.cpp).
//
// Coordinates. pagmo sees the unit box u in [0, 1]^p, x = lo + u (hi - lo), so its mutation
// and crossover act alike on every param whatever its unit. Fitness is the SSE over all cases
// (a failed simulation gets 1e30, so it is never the champion).
//
// Operators. Simulated binary crossover, polynomial mutation, tournament selection and sga's
// pure elitism (plugins/pagmo_sga/pagmo_sga.cpp): the champion never gets worse.
//
// Budget. `samples` evaluations (default 20 (p + 1) x 21, at least 200): a population of
// 10 (p + 1) capped at 100 (at least 8, even), and samples / population - 1 generations.
//
// Determinism and threads. sga evaluates its offspring one by one through the problem's
// fitness() (it has no batch-evaluator hook in pagmo 2.18), so generations run serially in the
// calling thread. The initial population, drawn with uniform01(seed, j, i), is evaluated in
// parallel with parallel_for (results stored by index). sga's own generator is seeded from
// `seed`. Hence the same seed gives the same result whatever the number of threads.

#include "kernel/calibration/optimizer.hpp"
#include "kernel/core/parallel.hpp"
#include "plugins/optimizer/pagmo_sga.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace thermnet {
namespace {

constexpr double kFailedFitness = 1e30;

/// The problem in the unit box, with counting and progress.
struct GaState {
  const CalibrationProblem* problem = nullptr;
  const OptimizerSettings* settings = nullptr;
  std::vector<double> lo, width;
  EvaluationOptions options;
  std::size_t total = 0;
  std::atomic<std::size_t> evaluations{0};
  std::atomic<std::size_t> ok{0};
  std::mutex mutex;
  double best_rmse = std::numeric_limits<double>::quiet_NaN();

  std::vector<double> to_x(const std::vector<double>& u) const {
    std::vector<double> x(u.size());
    for (std::size_t j = 0; j < u.size(); ++j)
      x[j] = lo[j] + width[j] * std::clamp(u[j], 0.0, 1.0);
    return x;
  }

  /// SSE of u (counted; reports progress); skipped (failed) once cancelled.
  double sse(const std::vector<double>& u) {
    if (settings->cancel && settings->cancel->load()) return kFailedFitness;
    Evaluation e = problem->evaluate(to_x(u), options);
    std::size_t done = ++evaluations;
    if (e.ok) ++ok;
    std::lock_guard<std::mutex> lock(mutex);
    if (e.ok && (std::isnan(best_rmse) || e.rmse < best_rmse)) best_rmse = e.rmse;
    if (settings->on_progress) settings->on_progress(Progress{done, total, best_rmse});
    return e.ok && std::isfinite(e.sse) ? e.sse : kFailedFitness;
  }
};

class GeneticAlgorithm final : public Optimizer {
public:
  OptimizerResult run(const CalibrationProblem& problem, const OptimizerSettings& s) override;
};

OptimizerResult GeneticAlgorithm::run(const CalibrationProblem& problem,
                                      const OptimizerSettings& s) {
  const auto t0 = std::chrono::steady_clock::now();
  OptimizerResult r;
  r.method = "ga";
  const std::size_t p = problem.dimension();
  if (p == 0) {
    r.notes.push_back("ga: the model has no ranged param");
    return r;
  }
  GaState state;
  state.problem = &problem;
  state.settings = &s;
  state.lo = problem.lower();
  state.width = problem.upper();
  for (std::size_t j = 0; j < p; ++j)
    state.width[j] -= state.lo[j];
  state.options.solver = s.solver;

  std::size_t pop_size = std::clamp<std::size_t>(10 * (p + 1), 8, 100);
  const std::size_t budget = s.samples > 0 ? s.samples : std::max<std::size_t>(200, pop_size * 21);
  pop_size = std::max<std::size_t>(2, std::min(pop_size, budget));
  pop_size += pop_size % 2;
  const std::size_t generations = budget > pop_size ? budget / pop_size - 1 : 0;
  state.total = pop_size * (generations + 1);

  // Initial population: reproducible draws, evaluated in parallel, stored by index.
  std::vector<std::vector<double>> initial(pop_size, std::vector<double>(p));
  for (std::size_t i = 0; i < pop_size; ++i)
    for (std::size_t j = 0; j < p; ++j)
      initial[i][j] = uniform01(s.seed, j, i);
  std::vector<double> fit(pop_size, kFailedFitness);
  parallel_for(
      pop_size, s.threads, [&](std::size_t i) { fit[i] = state.sse(initial[i]); }, s.cancel);
  const double initial_best = *std::min_element(fit.begin(), fit.end());

  SgaRequest request;
  request.initial = std::move(initial);
  request.initial_fitness = std::move(fit);
  request.generations = generations;
  request.seed = static_cast<unsigned>((s.seed ^ (s.seed >> 32)) & 0xffffffffu);
  request.fitness = [&state](const std::vector<double>& u) { return state.sse(u); };
  request.cancelled = [&s] { return s.cancel && s.cancel->load(); };
  const SgaOutcome evolved = load_pagmo_sga()(request);
  const std::size_t done_generations = evolved.generations;

  r.samples = pop_size * (done_generations + 1);
  r.evaluations = state.evaluations.load();
  r.simulations = r.evaluations * problem.cases().size();
  r.cancelled = s.cancel && s.cancel->load();
  const double best = evolved.champion_fitness;
  if (best < kFailedFitness) {
    r.found = true;
    r.best = state.to_x(evolved.champion_x);
    // The champion's RMSE and R^2 (sga keeps only its fitness): one more evaluation.
    Evaluation e = problem.evaluate(r.best, state.options);
    ++r.evaluations;
    r.simulations += problem.cases().size();
    r.rmse = e.ok ? e.rmse : std::sqrt(best / static_cast<double>(problem.points()));
    r.r2 = e.ok ? e.r2 : problem.r_squared(best);
    r.accepted = state.ok.load();
    const auto n = static_cast<double>(problem.points());
    r.notes.push_back(fmt::format(
        "ga: pagmo sga, population {}, {} generations; best RMSE of the initial population "
        "{} -> {:.4g} K",
        pop_size, done_generations,
        initial_best < kFailedFitness ? fmt::format("{:.4g} K", std::sqrt(initial_best / n))
                                      : std::string("none"),
        r.rmse));
  } else {
    r.notes.push_back("ga: no sample could be simulated");
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

OptimizerPlugin make_ga() {
  return {
      .name = "ga",
      .doc =
          "pagmo2's simple genetic algorithm (sga): SBX crossover, polynomial mutation, tournament "
          "selection, elitism, in the unit box of the ranges",
      .create = [] { return std::make_unique<GeneticAlgorithm>(); },
      .budget = "evaluations (>= 200): population 10 (p + 1) <= 100, then generations"};
}

} // namespace
THERMNET_REGISTER(OptimizerPlugin, make_ga);
} // namespace thermnet
