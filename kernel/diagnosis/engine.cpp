// The evidence/fit engine's entry points: the baseline, bases with applied findings, the
// evaluation of a candidate (fit on all data, validation folds, gain; spread over processes and
// threads for many candidates), and the curves.

#include "kernel/diagnosis/engine.hpp"
#include "kernel/diagnosis/statistics.hpp"

#include "kernel/calibration/least_squares.hpp"
#include "kernel/core/process_group.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <mutex>
#include <utility>

namespace thermnet::detail {

Engine::Engine(const lang::Model& model, const DiagnosisOptions& options)
    : model_(model), opt_(options) {
  load_cases();
  simulate_baseline();
  make_folds();
  base0_ = make_base({});
}

std::vector<StoredResiduals> Engine::series_residuals(const CaseSims& sims) const {
  std::vector<StoredResiduals> out;
  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    const auto& m = ev_.cases[c].measured;
    for (std::size_t s = 0; s < m.series.size(); ++s) {
      out.emplace_back();
      out.back().reserve(m.times.size());
      for (std::size_t k = 0; k < m.times.size(); ++k)
        if (!std::isnan(m.series[s].values[k]))
          out.back().push_back(static_cast<float>(sims[c][s][k] - m.series[s].values[k]));
    }
  }
  return out;
}

bool same_candidate(const Candidate& a, const Candidate& b) {
  return a.kind == b.kind && a.nodes == b.nodes && a.mechanism == b.mechanism &&
         a.element == b.element;
}

void write_extension(Finding& f, const Hypothesis& h, const Candidate& c,
                     const std::vector<double>& p, const Evidence& ev) {
  f.statement = h.statement(c, p, ev);
  f.case_statements = h.case_statements(c, p, ev);
  f.param_rewrites = h.rewrites(c, p);
  f.retired = h.retires(c, ev);
  mark_bounds(f, c, p);
}

void mark_bounds(Finding& f, const Candidate& c, const std::vector<double>& p) {
  f.at_bounds.clear();
  for (std::size_t j = 0; j < p.size() && j < c.names.size(); ++j)
    if (c.names[j] == kStartShare) // both ends are starts of their own, not limits
      continue;
    else if (on_bound(c, p, j, false))
      f.at_bounds[c.names[j]] = "lower";
    else if (on_bound(c, p, j, true))
      f.at_bounds[c.names[j]] = "upper";
}

Base Engine::make_base(std::vector<Applied> applied, bool measured) const {
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
  b.sse_all = sum_of_squares(r);
  b.holdout_r.reserve(n_test_); // (sized once, as in validate())
  for (std::size_t f = 0; f < folds(); ++f) {
    residuals(b.sims, Part{Part::test, f}, r);
    b.sse_test += sum_of_squares(r);
    for (double x : r)
      b.holdout_r.push_back(static_cast<float>(x));
  }
  b.r = series_residuals(b.sims);
  if (!measured) return b;
  b.metrics = metrics(b.sims);
  b.at_floor = at_floor(b.metrics);
  return b;
}

template <class Work>
void Engine::timed(const Base& base, bool joint, std::size_t refits, Work&& work) const {
  const auto wall0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  const std::size_t sims0 = simulations_.load(), sens0 = sensitivity_runs_.load();
  work();
  RefitBatch b;
  b.base_findings = base.applied.size();
  b.joint = joint;
  b.refits = refits;
  b.simulations = simulations_.load() - sims0;
  b.sensitivity_runs = sensitivity_runs_.load() - sens0;
  b.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  b.cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  if (!batches_.empty() && batches_.back().base_findings == b.base_findings &&
      batches_.back().joint == joint) {
    RefitBatch& last = batches_.back();
    last.refits += b.refits;
    last.simulations += b.simulations;
    last.sensitivity_runs += b.sensitivity_runs;
    last.wall_s += b.wall_s;
    last.cpu_s += b.cpu_s;
  } else {
    batches_.push_back(b);
  }
}

Evaluated Engine::evaluate(const Entry& e, const Base& base, bool joint) const {
  Refit r;
  timed(base, joint, 1, [&] { r = refit(e, base, joint); });
  return evaluated(e, base, std::move(r));
}

Refit Engine::refit(const Entry& e, const Base& base, bool joint) const {
  Refit out;
  const Stack stack(&base.applied, e.h, &e.c);
  const Hypothesis& h = base.applied.empty() ? *e.h : stack;
  // The joint refit (many parameters, started at the recalibrated values) stops earlier; a fold's
  // refit starts at the all-data optimum (one step for a joint refit).
  const int max_iter = joint ? 12 : 30, fold_iter = joint ? 1 : 3;
  const double rtol = joint ? 1e-5 : 1e-7;
  // 1. Fit on all data: the reported values.
  Fit b = fit_all_data(h, e.c, base, max_iter, rtol);
  if (!b.ok) return out;
  out.moved = b.moved;
  // 2. Validation: refit without each fold's held-out points, score on them (the folds start
  // from the all-data fit, its residuals and Jacobian).
  std::vector<double> holdout_r;
  const bool validated = validate(h, e.c, b, base, fold_iter, rtol, holdout_r);
  // The residuals are kept in single precision as soon as they are computed: a batch's refits
  // all wait for the batch to end (a 10^6-row file's 23 joint refits held 0.7 GB of doubles).
  out.holdout_r.assign(holdout_r.begin(), holdout_r.end());
  if (!validated) return out;
  out.ok = true;
  out.p = std::move(b.p);
  out.se = std::move(b.se);
  out.sse = b.sse;
  out.holdout_sse = sum_of_squares(holdout_r);
  out.r.assign(b.r.begin(), b.r.end());
  // (every test of the candidate needs it: measured once, here, in parallel with the refits)
  out.holdout_rho = positive_autocorrelation(holdout_r, segments_);
  return out;
}

Evaluated Engine::evaluated(const Entry& e, const Base& base, Refit refit) const {
  Evaluated out;
  Finding& f = out.f;
  f.candidate = e.c;
  f.evidence = e.c.evidence;
  f.given = static_cast<int>(base.applied.size());
  out.holdout_r = std::move(refit.holdout_r);
  out.holdout_rho = std::move(refit.holdout_rho);
  if (!refit.ok) return out;
  out.holdout_sse = refit.holdout_sse;
  // Residuals per series (the all-data rows, in order) for the mechanism comparison, each sized
  // exactly: every refitted candidate keeps them (grown by push_back, 5-50 % more).
  std::size_t row = 0;
  for (const auto& ce : ev_.cases)
    for (const auto& s : ce.measured.series) {
      out.r.emplace_back();
      out.r.back().reserve(static_cast<std::size_t>(std::count_if(
          s.values.begin(), s.values.end(), [](double v) { return !std::isnan(v); })));
      for (double v : s.values)
        if (!std::isnan(v)) out.r.back().push_back(refit.r[row++]);
    }
  f.values = refit.p;
  // Failed: no step from any start, and the start itself no better than the model it extends
  // (an offset's start, the mean residual, is often already its optimum: not a failure).
  f.fit_failed = !refit.moved && !(refit.sse < base.sse_all);
  if (!e.c.start_T.empty()) f.start = "the node it adds " + start_words(e.c, refit.p);
  f.std_errors = std::move(refit.se);
  out.degenerate = e.h->degenerate(e.c, refit.p);
  measure_gain(f, base, refit.sse, out.holdout_sse);
  write_extension(f, *e.h, e.c, refit.p, ev_);
  return out;
}

namespace {
/// Iterations of a fit from one of a kind's other starts: enough to show where it leads.
constexpr int kBriefIterations = 3;
} // namespace

Engine::Fit Engine::fit_all_data(const Hypothesis& h, const Candidate& c, const Base& base,
                                 int max_iter, double rtol) const {
  // From the candidate's start, then briefly (kBriefIterations) from each of its kind's
  // other starts (a mass's place and time constant: from one start a refit can stay where it
  // began, the building envelope's wall at its first guess); the best brief fit, when it beats the
  // first, goes on from there with the full count (one continuation, not one per improvement).
  // The standard errors are those of the fit kept, found once at the end: a restart's covariance
  // (its own copies of the Jacobian) is not made beside the fits still alive.
  Fit best = fit(h, c, c.start, Part{}, base, max_iter, rtol, nullptr, false);
  bool moved = best.ok && best.moved;
  // (the best brief fit's point and SSE only: its residuals and Jacobian would live beside the
  // next brief fit's for nothing, as the continuation starts again from its point)
  std::vector<double> lead;
  double lead_sse = std::numeric_limits<double>::infinity();
  for (const auto& s : h.restarts(c)) {
    Fit a = fit(h, c, s, Part{}, base, kBriefIterations, rtol, nullptr, false);
    if (!a.ok) continue;
    moved = moved || a.moved;
    if (a.sse < lead_sse) {
      lead_sse = a.sse;
      lead = std::move(a.p);
    }
  }
  if (!lead.empty() && (!best.ok || lead_sse < best.sse)) {
    Fit more = fit(h, c, lead, Part{}, base, max_iter, rtol, nullptr, false);
    if (more.ok && (!best.ok || more.sse < best.sse)) best = std::move(more);
  }
  best.moved = moved;
  if (best.ok) set_std_errors(c, best);
  return best;
}

bool Engine::validate(const Hypothesis& h, const Candidate& c, const Fit& all, const Base& base,
                      int max_iter, double rtol, std::vector<double>& holdout_r) const {
  std::vector<double> r;
  // Where the node a candidate adds starts (its start share) is held at the all-data fit in the
  // folds, as the measured starts are: a fold without the case's first stretch cannot tell it,
  // and a fit free to move it there moves it anywhere.
  Candidate held = c;
  for (std::size_t j = 0; j < held.names.size() && j < all.p.size(); ++j)
    if (held.names[j] == kStartShare) {
      held.lo[j] = all.p[j] - 1e-9;
      held.hi[j] = all.p[j] + 1e-9;
    }
  // Sized once: appended fold by fold it grew to 4/3 of the held-out points, and every refitted
  // candidate keeps it (608 instead of 456 MB for 19 candidates of a 10^6-row file).
  holdout_r.reserve(holdout_r.size() + n_test_);
  for (std::size_t k = 0; k < folds(); ++k) {
    try {
      if (!determined_in(held, all, Part{Part::train, k})) {
        // The fold's fitted data cannot tell some parameter (an event none of them holds): the
        // candidate cannot predict its held-out data, which are scored as the base predicts them
        // (no gain there; a refit would keep the all-data value, fitted on those very data).
        residuals(base.sims, Part{Part::test, k}, r);
      } else {
        const Fit a = fit(h, held, all.p, Part{Part::train, k}, base, max_iter, rtol, &all, false);
        if (!a.ok) return false;
        // The held-out points from the fit's own simulation at its optimum where it holds them
        // (a split case's other stretches), or the all-data fit's when the fold did not move.
        const Part test{Part::test, k};
        if (covers(a.sims, test))
          residuals(a.sims, test, r);
        else if (a.p == all.p && covers(all.sims, test))
          residuals(all.sims, test, r);
        else
          residuals(simulate(&h, &c, a.p, test, base), test, r);
      }
    } catch (const std::exception&) {
      return false;
    }
    holdout_r.insert(holdout_r.end(), r.begin(), r.end());
  }
  return true;
}

bool Engine::determined_in(const Candidate& c, const Fit& all, Part part) const {
  // Every column of the all-data Jacobian has an effect on the part's points.
  if (all.J.rows() != static_cast<long>(all.r.size())) return true; // no Jacobian: unknown
  const std::vector<char>& in = rows_in(part);
  for (long j = 0; j < all.J.cols(); ++j) {
    if (static_cast<std::size_t>(j) < c.names.size() &&
        c.names[static_cast<std::size_t>(j)] == kStartShare)
      continue; // held in the folds
    bool effect = false;
    for (long i = 0; i < all.J.rows() && !effect; ++i)
      effect = in[static_cast<std::size_t>(i)] && all.J(i, j) != 0.0;
    if (!effect) return false;
  }
  return true;
}

void Engine::measure_gain(Finding& f, const Base& base, double sse, double holdout_sse) const {
  const double na = static_cast<double>(points()), nt = std::max(1.0, static_cast<double>(n_test_));
  const double k = static_cast<double>(f.candidate.start.size());
  f.rmse_before = std::sqrt(base.sse_all / na);
  f.rmse_after = std::sqrt(sse / na);
  const double total = sst(Part{});
  double total_test = 0.0;
  for (std::size_t j = 0; j < folds(); ++j)
    total_test += sst(Part{Part::test, j});
  constexpr double undefined = std::numeric_limits<double>::quiet_NaN(); // data without spread
  f.r2_before = total > 0 ? 1.0 - base.sse_all / total : undefined;
  f.r2_after = total > 0 ? 1.0 - sse / total : undefined;
  f.validation_rmse_before = std::sqrt(base.sse_test / nt);
  f.validation_rmse_after = std::sqrt(holdout_sse / nt);
  f.validation_r2_before = total_test > 0 ? 1.0 - base.sse_test / total_test : undefined;
  f.validation_r2_after = total_test > 0 ? 1.0 - holdout_sse / total_test : undefined;
  f.delta_bic = delta_bic(sse, base.sse_all, k);
}

std::vector<Evaluated> Engine::evaluate_all(const std::vector<Entry>& entries, const Base& base,
                                            bool joint) const {
  // Each process refits its share of the entries; the refits are exchanged, and every process
  // makes the same findings from all of them.
  std::vector<Refit> refits(entries.size());
  const std::string stage =
      fmt::format("refitting candidates{}{}", joint ? " jointly with the ranged params" : "",
                  base.applied.empty() ? std::string()
                                       : fmt::format(" given {} finding{}", base.applied.size(),
                                                     base.applied.size() == 1 ? "" : "s"));
  std::atomic<std::size_t> done{0};
  std::mutex told;
  const auto tell = [&](std::size_t n) {
    if (!opt_.progress) return;
    std::lock_guard lock(told);
    opt_.progress({stage, n, entries.size()});
  };
  tell(0);
  timed(base, joint, entries.size(), [&] {
    distributed_for(
        entries.size(), opt_.threads,
        [&](std::size_t i) {
          refits[i] = refit(entries[i], base, joint);
          tell(++done);
        },
        [&](std::size_t i) { return pack_refit(refits[i]); },
        [&](std::size_t i, std::string_view bytes) { refits[i] = unpack_refit(bytes); });
  });
  std::vector<Evaluated> res(entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i)
    res[i] = evaluated(entries[i], base, std::move(refits[i]));
  return res;
}

std::string pack_refit(const Refit& refit) {
  std::string out;
  append_bytes(out, refit.ok);
  append_bytes(out, refit.moved);
  append_values(out, refit.p);
  append_values(out, refit.se);
  append_bytes(out, refit.sse);
  append_bytes(out, refit.holdout_sse);
  append_values(out, refit.r);
  append_values(out, refit.holdout_r);
  append_values(out, refit.holdout_rho);
  return out;
}

Refit unpack_refit(std::string_view bytes) {
  Refit refit;
  refit.ok = take_bytes<bool>(bytes);
  refit.moved = take_bytes<bool>(bytes);
  refit.p = take_values<double>(bytes);
  refit.se = take_values<double>(bytes);
  refit.sse = take_bytes<double>(bytes);
  refit.holdout_sse = take_bytes<double>(bytes);
  refit.r = take_values<float>(bytes);
  refit.holdout_r = take_values<float>(bytes);
  refit.holdout_rho = take_values<double>(bytes);
  return refit;
}

double Engine::delta_bic(double sse_after, double sse_before, double k) const {
  const double na = static_cast<double>(points());
  const double floor2 = std::max(ev_.noise_floor * ev_.noise_floor, 1e-12) * 1e-4;
  return na * std::log((sse_after + floor2 * na) / (sse_before + floor2 * na)) + k * std::log(na);
}

std::vector<DiagnosisReport::Curves> Engine::curves(const Base& after, const Base& all) const {
  std::vector<DiagnosisReport::Curves> out;
  const bool with_after = !after.applied.empty();

  for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
    DiagnosisReport::Curves cv;
    cv.case_name = ev_.cases[c].name;
    cv.times = ev_.cases[c].times();
    for (std::size_t s = 0; s < ev_.cases[c].measured.series.size(); ++s) {
      const std::string& n = ev_.cases[c].measured.series[s].node;
      cv.measured[n] = ev_.cases[c].measured.series[s].values;
      cv.before[n] = base0_.sims[c][s];
      if (with_after) cv.after[n] = after.sims[c][s];
    }
    out.push_back(std::move(cv));
  }
  // Each finding's own step: the models with the first k findings (at their final values), one
  // at a time (a base holds every measured point's simulation and residuals); the last is `all`.
  const std::size_t K = all.applied.size();
  for (std::size_t k = 1; k <= K; ++k) {
    const Base made =
        k < K ? make_base(std::vector<Applied>(
                    all.applied.begin(), all.applied.begin() + static_cast<std::ptrdiff_t>(k)))
              : Base{};
    const Base& b = k < K ? made : all;
    for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
      out[c].steps.emplace_back();
      for (std::size_t s = 0; s < ev_.cases[c].measured.series.size(); ++s)
        out[c].steps.back()[ev_.cases[c].measured.series[s].node] = b.sims[c][s];
    }
  }
  return out;
}

} // namespace thermnet::detail
