// Judging refitted candidates: significance, one finding per site whatever its mechanisms (named
// only when the data tell them apart), and the ranking.

#include "kernel/diagnosis/selection.hpp"

#include "kernel/core/parallel.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace thermnet::detail {

void note_mechanism(Finding& keep, const Finding& drop, const FitComparison& cmp,
                    const std::vector<std::string>& mechanisms) {
  keep.mechanism_z = cmp.z;
  keep.mechanism_identified = cmp.separable;
  const std::string numbers = fmt::format(
      "RMSE {:.4g} vs {:.4g} K, held-out {:.4g} vs {:.4g} K; difference {:.2g} times its "
      "spread over {:.0f} independent points",
      keep.rmse_after, drop.rmse_after, keep.validation_rmse_after, drop.validation_rmse_after,
      cmp.z, cmp.n_eff);
  keep.mechanism_note =
      cmp.separable ? fmt::format("{} fits better than {} ({})", keep.candidate.mechanism,
                                  drop.candidate.mechanism, numbers)
                    : fmt::format("{} fit equally ({}); kept {}", fmt::join(mechanisms, " and "),
                                  numbers, keep.candidate.mechanism);
}

void Selection::judge(std::vector<Evaluated>& res, const Base& reference) const {
  // Better by the information criterion, a real drop of the error, and a held-out gain over the
  // reference (the model the candidate is added to) beyond chance: the paired test on the
  // held-out residuals (holdout_gain_z), counting independent points only, and beyond the
  // practical floor where it matters most.
  // Each candidate's test is its own (the paired test costs the held-out points times their
  // correlation's lags: hundreds of candidates of a 72-node panel took seconds): in parallel.
  const double nf = engine_.evidence().noise_floor;
  const double z_min = threshold(res);
  parallel_for(res.size(), opt_.threads, [&](std::size_t i) {
    Evaluated& e = res[i];
    Finding& f = e.f;
    if (f.values.empty()) return;
    f.holdout_z = 0.0;
    f.window_gain = std::numeric_limits<double>::infinity();
    f.significant = !e.degenerate && !f.fit_failed && f.delta_bic < kSignificantBic &&
                    f.validation_rmse_after <= f.validation_rmse_before + 0.1 * nf &&
                    f.rmse_after < 0.97 * f.rmse_before;
    judge_against(e, compare_to(e, reference.holdout_r, reference.r), z_min);
  });
}

double Selection::threshold(const std::vector<Evaluated>& res) {
  // (the candidates refitted together, the comparisons a step makes)
  return significant_gain_z_for(static_cast<std::size_t>(std::count_if(
      res.begin(), res.end(), [](const Evaluated& e) { return !e.f.values.empty(); })));
}

Comparison Selection::compare_to(const Evaluated& e, const StoredResiduals& holdout_r,
                                 const std::vector<StoredResiduals>& r) const {
  // The output-error criterion's test of a candidate against one reference fit (its held-out and
  // all-data residuals): the held-out gain beyond the variation neither explains, and the largest
  // local gain beyond the practical floor.
  // And the gain in every validation block: a large gain on each stretch of data (or case) not
  // used to fit it is confirmed however few independent points correlated residuals hold (a
  // building's 140 h of 5-minute samples counted as about 5 by the z test).
  Comparison c{holdout_gain_z(holdout_r, e.holdout_r, e.holdout_rho, engine_.evidence().noise_floor,
                              engine_.holdout_segments()),
               largest_window_gain(r, e.r)};
  c.block_gain = worst_block_gain(holdout_r, e.holdout_r, engine_.fold_points());
  c.confirmed = engine_.folds() >= kConfirmingBlocks && c.block_gain >= kConfirmingBlockGain;
  return c;
}

void Selection::judge_against(Evaluated& e, const Comparison& cmp, double z_min) const {
  // A finding must pass the test against every reference; z and the gain kept are the smallest.
  // z_min: the threshold for the candidates compared in the step.
  Finding& f = e.f;
  const bool first = f.window_gain == std::numeric_limits<double>::infinity();
  f.holdout_z = f.window_gain == std::numeric_limits<double>::infinity()
                    ? cmp.z
                    : std::min(f.holdout_z, cmp.z);
  f.block_gain = first ? cmp.block_gain : std::min(f.block_gain, cmp.block_gain);
  f.window_gain = std::min(f.window_gain, cmp.gain);
  f.significant = f.significant && (cmp.z >= z_min || cmp.confirmed) && cmp.gain >= opt_.min_gain;
}

void Selection::add_rivals(Finding& f, std::size_t best, const std::vector<Entry>& entries,
                           const std::vector<Evaluated>& res) const {
  // Candidates the data cannot tell from the finding are listed with it: one finding, its rivals.
  // The test is the mechanisms' one (compare_fits: the SSE difference against the sampling
  // spread of an SSE over the independent points, and the held-out error agreeing); the residual
  // model error (params never fit exactly) makes a noise-only paired test too sharp here.
  const double nf = engine_.evidence().noise_floor;
  for (std::size_t i : ranked(res)) {
    const Finding& g = res[i].f;
    if (i == best || site(g.candidate) == site(f.candidate) || entries[i].own_h->recalibrates())
      continue;
    const FitComparison cmp =
        compare_fits({res[best].r, res[best].holdout_sse}, {res[i].r, res[i].holdout_sse}, nf);
    if (cmp.separable && cmp.first_better) continue;
    if (f.rivals.size() + 1 >= opt_.top) break;
    f.rivals.push_back({g.candidate, g.values, g.rmse_after, g.validation_rmse_after, cmp.z});
  }
  if (f.rivals.empty()) return;
  // What would separate them: a sensor on a node one of them names that has none; a second sensor
  // where a sensor fault competes with a model cause; else a heater schedule that excites them.
  const Evidence& ev = engine_.evidence();
  std::vector<Candidate> all{f.candidate};
  for (const auto& r : f.rivals)
    all.push_back(r.candidate);
  std::set<std::string> unmeasured, sensed;
  bool measurement = false, model = false;
  for (const auto& c : all) {
    (c.measurement_side ? measurement : model) = true;
    for (const auto& n : c.nodes) {
      const int i = ev.node_index(n);
      if (i >= 0 && !ev.measured(i) &&
          !ev.cases.front().spec.nodes[static_cast<std::size_t>(i)].boundary)
        unmeasured.insert(n);
      if (c.measurement_side) sensed.insert(n);
    }
  }
  std::vector<std::string> ways;
  if (!unmeasured.empty())
    ways.push_back(fmt::format("a sensor on {} (not measured; the candidates differ there)",
                               fmt::join(unmeasured, ", ")));
  if (measurement && model)
    ways.push_back(fmt::format("a second sensor beside {} (a sensor fault moves only its own "
                               "reading)",
                               fmt::join(sensed, ", ")));
  if (ways.empty() || model)
    ways.push_back("a case whose heater powers step at different times than in the data (the "
                   "candidates' responses to a step differ in size and delay)");
  f.separate_by = fmt::format("{}", fmt::join(ways, "; or "));
}

void Selection::merge_mechanisms(const std::vector<Entry>& entries,
                                 std::vector<Evaluated>& res) const {
  // One site refitted with two mechanisms (a link as linear and as radiation): one finding. The
  // mechanism is named only when the data tell them apart (compare_fits: the SSE difference beyond
  // the spread of an SSE over the independent points, and the better one also better on held-out
  // data).
  for (std::size_t i = 0; i < res.size(); ++i)
    for (std::size_t j = i + 1; j < res.size(); ++j) {
      Evaluated &a = res[i], &b = res[j];
      if (a.f.values.empty() || b.f.values.empty() || a.f.candidate.mechanism.empty() ||
          site(a.f.candidate) != site(b.f.candidate) ||
          a.f.candidate.mechanism == b.f.candidate.mechanism)
        continue;
      const FitComparison cmp =
          compare_fits({a.r, a.holdout_sse}, {b.r, b.holdout_sse}, engine_.evidence().noise_floor);
      Evaluated& keep = cmp.first_better ? a : b;
      Evaluated& drop = cmp.first_better ? b : a;
      note_mechanism(keep.f, drop.f, cmp, entries[i].own_h->mechanisms());
      drop.f.values.clear(); // merged into keep
    }
}

double Selection::score(const Finding& f) const {
  // Predictive error on held-out data plus the information criterion on all data.
  const double na = static_cast<double>(engine_.points());
  const double nt = std::max(1.0, static_cast<double>(engine_.held_out_points()));
  const double all2 = std::max(f.rmse_after * f.rmse_after, 1e-300);
  const double hold2 = std::max(f.validation_rmse_after * f.validation_rmse_after, 1e-300);
  return nt * std::log(hold2) + na * std::log(all2) +
         static_cast<double>(f.values.size()) * std::log(na);
}

std::vector<std::size_t> Selection::ranked(const std::vector<Evaluated>& res,
                                           bool significant_only) const {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < res.size(); ++i)
    if (!res[i].f.values.empty() &&
        (significant_only ? res[i].f.significant : res[i].f.rmse_after < res[i].f.rmse_before))
      idx.push_back(i);
  std::stable_sort(idx.begin(), idx.end(),
                   [&](std::size_t a, std::size_t b) { return score(res[a].f) < score(res[b].f); });
  return idx;
}

} // namespace thermnet::detail
