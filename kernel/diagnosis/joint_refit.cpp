// The joint refit. When recalibrating the ranged params alone is significant (the recalibrating
// candidate beats the baseline by the information criterion), the model's params are wrong too, so
// a candidate's own parameter fitted at the declared values says little. Every refitted
// model-side candidate is then refitted again with its parameter and every ranged param together
// (bounded, started at the recalibrated values) and compared on that footing: the joint result
// replaces its own-parameter refit, and its extra parameter must also beat the recalibration alone
// by the BIC margin (otherwise the recalibration explains it).

#include "kernel/diagnosis/selection.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <limits>

namespace thermnet::detail {

std::vector<double> Selection::joint_refit(DiagnosisReport& rep) {
  std::vector<double> vs_recalibration(chosen_.size(), -std::numeric_limits<double>::infinity());
  std::size_t recal = chosen_.size();
  for (std::size_t i = 0; i < chosen_.size(); ++i)
    if (chosen_[i].own_h->recalibrates()) recal = i;
  if (recal == chosen_.size() || res_[recal].f.values.empty() || !(res_[recal].f.delta_bic < -10.0))
    return vs_recalibration;
  const std::vector<double> ranged = res_[recal].f.values;
  add_recalibrated_shortlist(recal, ranged, vs_recalibration);
  refit_jointly(recal, ranged, vs_recalibration, rep);
  return vs_recalibration;
}

void Selection::add_recalibrated_shortlist(std::size_t recal, const std::vector<double>& ranged,
                                           std::vector<double>& vs_recalibration) {
  // The screen is repeated at the recalibrated params (the unexplained heat flows change with
  // them): twice as many sites (a weak guide at wrong params, many near-equal sites after).
  try {
    const Base base = engine_.make_base({Applied{chosen_[recal].h, chosen_[recal].c, ranged}});
    const Evidence ev = engine_.evidence_at(base);
    for (auto& e : shortlisted(screen(ev).side, ev, 2 * opt_.refits, nullptr))
      if (std::none_of(chosen_.begin(), chosen_.end(),
                       [&](const Entry& x) { return same_candidate(x.c, e.c); })) {
        chosen_.push_back(std::move(e));
        res_.emplace_back(); // no own-parameter refit: evaluated jointly only
        vs_recalibration.push_back(-std::numeric_limits<double>::infinity());
      }
  } catch (const std::exception&) {
    // the recalibrated screen failed: the declared-value shortlist only
  }
}

void Selection::refit_jointly(std::size_t recal, const std::vector<double>& ranged,
                              std::vector<double>& vs_recalibration, DiagnosisReport& rep) {
  std::vector<std::size_t> todo;
  std::vector<Entry> entries;
  for (std::size_t i = 0; i < chosen_.size(); ++i) {
    if (!model_side(chosen_[i])) continue;
    joints_.push_back(
        std::make_unique<Joint>(chosen_[i].h, chosen_[i].c, chosen_[recal].h, chosen_[recal].c));
    todo.push_back(i);
    Entry je = chosen_[i];
    je.h = joints_.back().get();
    je.c = joints_.back()->candidate(ranged);
    entries.push_back(std::move(je));
  }
  std::vector<Evaluated> jres = engine_.evaluate_all(entries, engine_.declared(), true);
  rep.refitted += todo.size();
  const double na = static_cast<double>(engine_.points());
  const double sse_recal = res_[recal].f.rmse_after * res_[recal].f.rmse_after * na;
  for (std::size_t j = 0; j < todo.size(); ++j) {
    if (jres[j].f.values.empty()) continue; // the joint fit failed: keep the own refit
    const std::size_t i = todo[j];
    const double sse = jres[j].f.rmse_after * jres[j].f.rmse_after * na;
    const double extra = static_cast<double>(chosen_[i].own.start.size());
    vs_recalibration[i] = engine_.delta_bic(sse, sse_recal, extra);
    jres[j].f.evidence += (jres[j].f.evidence.empty() ? "" : "; ") +
                          fmt::format("refitted jointly with the ranged params ({})",
                                      fmt::join(chosen_[recal].c.names, ", "));
    res_[i] = std::move(jres[j]);
    chosen_[i] = std::move(entries[j]);
  }
}

} // namespace thermnet::detail
