// The selection's stages in order: the screen's shortlist refitted on the declared model (widened
// when the screen is a poor guide; refitted jointly only when recalibrating the ranged params is
// significant), the joint refit with the ranged params, the first ranking, the greedy forward
// selection, and the report's ranks, alternatives and rejected candidates.

#include "kernel/diagnosis/selection.hpp"

#include "kernel/core/parallel.hpp"

#include <algorithm>
#include <optional>

namespace thermnet::detail {

Selection::Selection(const Engine& engine, const DiagnosisOptions& options)
    : engine_(engine), opt_(options) {
  for (const auto& name : HypothesisRegistry::global().names())
    hyps_.push_back(HypothesisRegistry::global().find(name)->create());
}

Base Selection::run(DiagnosisReport& rep, Base& last) {
  refit_shortlist(rep);
  const std::size_t recal = joint_refit(rep);
  rank_first(recal);
  if (refit_tied_variants(recal, rep)) rank_first(recal);
  const Base best = select_forward(rep, last);
  finish(rep);
  // (here, while the hypotheses the findings name are alive: the curves simulate their steps)
  rep.curves = engine_.curves(best, last);
  return best;
}

void Selection::refit_shortlist(DiagnosisReport& rep) {
  // Every plugin proposes.
  Screened s = screen(engine_.evidence());
  rep.screened = s.side.size() + s.others.size();
  side_ = std::move(s.side);
  chosen_ = std::move(s.others);
  // The recalibration and the measurement-side candidates are refitted first. When recalibrating
  // the ranged params is significant, every model-side candidate is refitted jointly with them
  // (joint_refit), which replaces its own refit at the declared params: that refit, and the
  // widening it would guide, are skipped (a third of a 150-node plate's simulations).
  res_ = engine_.evaluate_all(chosen_, engine_.declared());
  rep.refitted = chosen_.size();
  std::size_t sites = opt_.refits;
  std::set<std::size_t> taken;
  std::vector<Entry> shortlist = shortlisted(side_, engine_.evidence(), sites, &taken);
  const bool joint_only = significant_recalibration() < chosen_.size();
  std::vector<Evaluated> own = joint_only
                                   ? std::vector<Evaluated>(shortlist.size()) // evaluated jointly
                                   : engine_.evaluate_all(shortlist, engine_.declared());
  for (std::size_t i = 0; i < shortlist.size(); ++i) {
    chosen_.push_back(std::move(shortlist[i]));
    res_.push_back(std::move(own[i]));
  }
  if (joint_only) return;
  widen(sites, taken);
  rep.refitted = chosen_.size();
}

std::size_t Selection::significant_recalibration() const {
  // (the recalibration's own held-out gain may be poor, e.g. many params fitted to one case: it
  // is enough that it improves the fit on all data)
  for (std::size_t i = 0; i < chosen_.size(); ++i)
    if (chosen_[i].own_h->recalibrates())
      return !res_[i].f.values.empty() && res_[i].f.delta_bic < kSignificantBic ? i
                                                                                : chosen_.size();
  return chosen_.size();
}

void Selection::widen(std::size_t sites, std::set<std::size_t>& taken) {
  // When the best refitted site sits in the last third of the shortlist's sites, the screen's
  // order is a poor guide here: the next sites are refitted too (at most twice).
  const std::vector<std::string> order = site_order(side_);
  for (int round = 0; round < 2; ++round) {
    judge(res_, engine_.declared());
    const auto best = ranked(res_);
    std::size_t pos = 0;
    for (std::size_t i : best)
      if (model_side(chosen_[i])) {
        pos = static_cast<std::size_t>(std::find(order.begin(), order.end(), site(chosen_[i].c)) -
                                       order.begin());
        break;
      }
    if (best.empty() || pos < sites - sites / 3 || pos >= order.size() || sites >= order.size())
      break;
    sites += opt_.refits;
    std::vector<Entry> more = shortlisted(side_, engine_.evidence(), sites, &taken);
    std::vector<Evaluated> mres = engine_.evaluate_all(more, engine_.declared());
    for (std::size_t i = 0; i < more.size(); ++i) {
      chosen_.push_back(std::move(more[i]));
      res_.push_back(std::move(mres[i]));
    }
  }
}

void Selection::rank_first(std::size_t recal) {
  // When recalibrating the ranged params alone is significant (`recal`), every other candidate
  // must beat that recalibration on held-out data by more than chance, not only the baseline.
  judge(res_, engine_.declared());
  if (recal < res_.size()) {
    const double z_min = threshold(res_);
    parallel_for(res_.size(), opt_.threads, [&](std::size_t i) {
      if (i == recal || res_[i].f.values.empty()) return;
      judge_against(res_[i], compare_to(res_[i], res_[recal].holdout_r, res_[recal].r), z_min);
    });
    std::vector<std::size_t> passed;
    for (std::size_t i = 0; i < res_.size(); ++i)
      if (i != recal && !res_[i].f.values.empty() && res_[i].f.significant) passed.push_back(i);
    against_own_params(passed, recal, z_min);
  }
  merge_mechanisms(chosen_, res_);
  first_ = ranked(res_);
}

void Selection::against_own_params(const std::vector<std::size_t>& passed, std::size_t recal,
                                   double z_min) {
  // A joint refit moves the params too: its gain over the recalibration may come from params the
  // recalibration's own refit did not reach (on a clean control, a radiative link with GR at its
  // lower bound passed), not from the candidate. So the candidate must also beat the params it was
  // fitted with, alone (held-out residuals at those all-data values: that favours the reference,
  // never the candidate). Those models are simulated in parallel (a 150-node plate's hundreds of
  // candidates took 5 s one after the other), each test into its own slot, and kept: the ranking
  // after the tied variants meets most of the same refits again.
  std::vector<std::size_t> todo;
  for (std::size_t i : passed) {
    const auto it = own_params_tests_.find(i);
    if (it == own_params_tests_.end() || it->second.values != res_[i].f.values ||
        it->second.holdout_sse != res_[i].holdout_sse)
      todo.push_back(i);
  }
  std::vector<OwnParamsTest> tests(todo.size());
  parallel_for(todo.size(), opt_.threads, [&](std::size_t k) {
    const Evaluated& e = res_[todo[k]];
    tests[k].values = e.f.values;
    tests[k].holdout_sse = e.holdout_sse;
    const std::size_t own = chosen_[todo[k]].own.names.size();
    if (e.f.values.size() != own + res_[recal].f.values.size()) return; // not refitted jointly
    const std::vector<double> params(e.f.values.begin() + static_cast<long>(own), e.f.values.end());
    try {
      const Base alone =
          engine_.make_base({Applied{chosen_[recal].h, chosen_[recal].c, params}}, false);
      tests[k].cmp = compare_to(e, alone.holdout_r, alone.r);
    } catch (const std::exception&) {
      // the params alone cannot be simulated: the comparison with the recalibration stands
    }
  });
  for (std::size_t k = 0; k < todo.size(); ++k)
    own_params_tests_[todo[k]] = std::move(tests[k]);
  for (std::size_t i : passed)
    if (const auto& cmp = own_params_tests_.at(i).cmp) judge_against(res_[i], *cmp, z_min);
}

void Selection::finish(DiagnosisReport& rep) {
  for (std::size_t i = 0; i < rep.findings.size(); ++i) {
    Finding& f = rep.findings[i];
    f.rank = static_cast<int>(i + 1);
    std::string words = engine_.trend_words(rep.baseline, f.candidate.nodes);
    if (!words.empty() && i == 0) f.evidence += (f.evidence.empty() ? "" : "; ") + words;
  }
  // Significant alone but not given the selected findings (proxies): alternatives.
  for (std::size_t i : first_)
    if (std::none_of(rep.findings.begin(), rep.findings.end(), [&](const Finding& f) {
          return site(f.candidate) == site(res_[i].f.candidate);
        }))
      if (rep.alternatives.size() < opt_.top) rep.alternatives.push_back(res_[i].f);
  for (auto& e : res_)
    if (!e.f.values.empty() && !e.f.significant) rep.rejected.push_back(std::move(e.f));
}

} // namespace thermnet::detail
