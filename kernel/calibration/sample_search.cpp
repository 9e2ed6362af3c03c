// sample_search(): the study's Monte Carlo acceptance and selection over any design of points.

#include "kernel/calibration/sample_search.hpp"

#include "kernel/core/parallel.hpp"
#include "kernel/core/process_group.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

namespace thermnet {

namespace {

/// Random streams: mc uses streams 0..d-1 (one per coordinate); the Latin hypercube uses its own.
constexpr std::uint64_t kLhsPermutationStream = std::uint64_t{1} << 32;
constexpr std::uint64_t kLhsJitterStream = std::uint64_t{2} << 32;

/// What became of one sample.
struct Outcome {
  enum class State : unsigned char { not_run, accepted, rejected, failed };
  State state = State::not_run;
  double rmse = 0.0;
  double r2 = 0.0;
  std::size_t simulations = 0;
  std::string failure; ///< why a failed sample failed
};

/// An outcome as bytes, for the processes that did not compute it (distributed_for).
std::string pack(const Outcome& o) {
  std::string out;
  append_bytes(out, o.state);
  append_bytes(out, o.rmse);
  append_bytes(out, o.r2);
  append_bytes(out, static_cast<std::uint64_t>(o.simulations));
  return out + o.failure;
}

/// The outcome pack() wrote.
Outcome unpack(std::string_view in) {
  Outcome o;
  o.state = take_bytes<Outcome::State>(in);
  o.rmse = take_bytes<double>(in);
  o.r2 = take_bytes<double>(in);
  o.simulations = static_cast<std::size_t>(take_bytes<std::uint64_t>(in));
  o.failure = std::string(in);
  return o;
}

/// Lowers `best` to `value` if smaller (lock-free; NaN means "none yet").
void lower_to(std::atomic<double>& best, double value) {
  double cur = best.load(std::memory_order_relaxed);
  while ((std::isnan(cur) || value < cur) &&
         !best.compare_exchange_weak(cur, value, std::memory_order_relaxed)) {
  }
}

} // namespace

std::vector<double> uniform_point(const std::vector<double>& lo, const std::vector<double>& hi,
                                  std::uint64_t seed, std::size_t i) {
  std::vector<double> x(lo.size());
  for (std::size_t j = 0; j < x.size(); ++j)
    x[j] = lo[j] + (hi[j] - lo[j]) * uniform01(seed, j, i);
  return x;
}

std::vector<std::vector<double>> latin_hypercube(std::size_t n, const std::vector<double>& lo,
                                                 const std::vector<double>& hi,
                                                 std::uint64_t seed) {
  std::vector<std::vector<double>> pts(n, std::vector<double>(lo.size()));
  std::vector<std::size_t> perm(n);
  for (std::size_t j = 0; j < lo.size(); ++j) {
    std::iota(perm.begin(), perm.end(), std::size_t{0});
    // Fisher-Yates with counter-based draws: the permutation depends on (seed, j) only.
    for (std::size_t k = n; k-- > 1;) {
      auto r = static_cast<std::size_t>(uniform01(seed, kLhsPermutationStream + j, k) *
                                        static_cast<double>(k + 1));
      std::swap(perm[k], perm[std::min(r, k)]);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const double u = (static_cast<double>(perm[i]) + uniform01(seed, kLhsJitterStream + j, i)) /
                       static_cast<double>(n);
      pts[i][j] = lo[j] + (hi[j] - lo[j]) * u;
    }
  }
  return pts;
}

OptimizerResult sample_search(const CalibrationProblem& problem, const OptimizerSettings& settings,
                              std::string method, std::size_t n,
                              const std::function<std::vector<double>(std::size_t)>& point) {
  OptimizerResult res;
  res.method = std::move(method);
  const auto start = std::chrono::steady_clock::now();
  if (problem.dimension() == 0 || problem.cases().empty()) {
    res.notes.push_back(problem.dimension() == 0 ? "no param has a range: nothing to calibrate"
                                                 : "no case has data: nothing to compare");
    return res;
  }
  EvaluationOptions eo;
  eo.tolerance = settings.tolerance;
  eo.solver = settings.solver;

  // Each process (MPI rank) evaluates its share of the samples; the outcomes are then exchanged,
  // so the reduction below sees them all, whatever the number of processes and threads.
  std::vector<Outcome> outcomes(n);
  const ProcessGroup& group = process_group();
  const auto [share_begin, share_end] = share_of(n, group.rank(), group.size());
  const std::size_t share = share_end - share_begin;
  std::atomic<std::size_t> done{0};
  std::atomic<double> best_rmse{std::numeric_limits<double>::quiet_NaN()};
  distributed_for(
      n, settings.threads,
      [&](std::size_t i) {
        const Evaluation e = problem.evaluate(point(i), eo);
        Outcome& o = outcomes[i];
        o.state = e.accepted ? Outcome::State::accepted
                  : e.ok     ? Outcome::State::rejected
                             : Outcome::State::failed;
        o.rmse = e.rmse;
        o.r2 = e.r2;
        o.simulations = e.simulations;
        if (!e.ok) o.failure = e.failure;
        if (e.accepted) lower_to(best_rmse, e.rmse);
        const std::size_t d = done.fetch_add(1) + 1;
        if (settings.on_progress) settings.on_progress(Progress{d, share, best_rmse.load()});
      },
      [&](std::size_t i) { return pack(outcomes[i]); },
      [&](std::size_t i, std::string_view bytes) { outcomes[i] = unpack(bytes); }, settings.cancel);

  // Reduce in index order: the result is the same whatever thread finished what.
  std::size_t best = n, failed = 0, failure_index = n;
  for (std::size_t i = 0; i < n; ++i) {
    const Outcome& o = outcomes[i];
    if (o.state == Outcome::State::not_run) continue;
    ++res.evaluations;
    res.simulations += o.simulations;
    if (o.state == Outcome::State::failed) {
      if (failed++ == 0) failure_index = i;
      continue;
    }
    if (o.state != Outcome::State::accepted) continue;
    ++res.accepted;
    if (best == n || o.rmse < outcomes[best].rmse) best = i;
  }
  res.cancelled = res.evaluations < n;
  res.samples = res.cancelled ? res.evaluations : n;
  if (best < n) {
    res.found = true;
    res.best = point(best);
    res.rmse = outcomes[best].rmse;
    res.r2 = outcomes[best].r2;
  } else {
    res.notes.push_back(fmt::format(
        "no sample was within the tolerance of {:g} K everywhere; widen the ranges, raise the "
        "tolerance or draw more samples",
        settings.tolerance));
  }
  if (failed > 0)
    res.notes.push_back(fmt::format("{} sample{} failed to simulate (sample {}: {})", failed,
                                    failed == 1 ? "" : "s", failure_index,
                                    outcomes[failure_index].failure));
  if (res.cancelled)
    res.notes.push_back(fmt::format("interrupted after {} of {} samples", res.evaluations, n));
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

} // namespace thermnet
