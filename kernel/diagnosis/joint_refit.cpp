// The joint refit. When recalibrating the ranged params alone is significant (the recalibrating
// candidate beats the baseline by the information criterion), the model's params are wrong too, so
// a candidate's own parameter fitted at the declared values says little. Every model-side candidate
// (not refitted at the declared params then: refit_shortlist) and the best measurement-side ones
// are refitted with their parameter and every ranged param together (bounded, started at the
// recalibrated values) and compared on that footing: the joint result replaces any own-parameter
// refit, and it must also beat the recalibration alone on held-out data (rank_first; otherwise the
// recalibration explains it). The counterparts on unmeasured nodes are refitted after the others,
// and only beside a proxy that gains, among the best of its kind (beside_gaining).

#include "kernel/diagnosis/selection.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <limits>
#include <optional>

namespace thermnet::detail {

std::size_t Selection::joint_refit(DiagnosisReport& rep) {
  const std::size_t recal = significant_recalibration();
  if (recal == chosen_.size()) return recal;
  const std::vector<double> ranged = res_[recal].f.values;
  std::optional<Base> recalibrated;
  try {
    recalibrated = engine_.make_base({Applied{chosen_[recal].h, chosen_[recal].c, ranged}});
    add_recalibrated_shortlist(*recalibrated);
  } catch (const std::exception&) {
    // the recalibrated model cannot be simulated: the declared-value shortlist only
  }
  refit_jointly(recal, ranged, recalibrated ? &*recalibrated : nullptr, rep);
  return recal;
}

void Selection::add_recalibrated_shortlist(const Base& base) {
  // The screen is repeated at the recalibrated params (the unexplained heat flows change with
  // them): twice as many sites (a weak guide at wrong params, many near-equal sites after). The
  // measurement-side candidates proposed there are added too: a sensor's lag is proposed only
  // where the residual follows the simulated slope, which the params' error can hide (D03 of the
  // validation table: a 423 s lag, not proposed at the declared params, was named an offset).
  try {
    const Evidence ev = engine_.evidence_at(base);
    Screened s = screen(ev);
    std::vector<Entry> more = shortlisted(s.side, ev, 2 * opt_.refits, nullptr);
    for (auto& e : s.others)
      if (e.c.measurement_side) more.push_back(std::move(e));
    for (auto& e : more) {
      const auto known = std::find_if(chosen_.begin(), chosen_.end(),
                                      [&](const Entry& x) { return same_candidate(x.c, e.c); });
      if (known == chosen_.end()) {
        chosen_.push_back(std::move(e));
        res_.emplace_back(); // no own-parameter refit: evaluated jointly only
      } else if (e.proxy.empty()) {
        known->proxy.clear(); // shortlisted by this screen: refitted as a proxy itself
      }
    }
  } catch (const std::exception&) {
    // the recalibrated screen failed: the declared-value shortlist only
  }
}

void Selection::refit_jointly(std::size_t recal, const std::vector<double>& ranged,
                              const Base* recalibrated, DiagnosisReport& rep) {
  // Measurement-side candidates (one per measured node and kind) are many: the ones whose own
  // refit helps most are refitted jointly (as many as the model-side shortlist's sites, twice).
  // Their refits on the recalibrated model rank them (they correct its series: no simulation);
  // at the declared params the params' error hides a sensor's (S12: a 61 s lag whose own refit
  // gained 0.3 % at the declared values).
  // (Those proposed only at the recalibrated params have no own refit: ranked by the second.)
  std::vector<std::size_t> meas;
  for (std::size_t i = 0; i < chosen_.size(); ++i)
    if (chosen_[i].c.measurement_side && (!res_[i].f.values.empty() || recalibrated))
      meas.push_back(i);
  std::vector<double> rmse(chosen_.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i : meas)
    if (!res_[i].f.values.empty()) rmse[i] = res_[i].f.rmse_after;
  if (recalibrated) {
    std::vector<Entry> on_recal;
    for (std::size_t i : meas)
      on_recal.push_back(chosen_[i]);
    const std::vector<Evaluated> r = engine_.evaluate_all(on_recal, *recalibrated);
    rep.refitted += on_recal.size();
    for (std::size_t j = 0; j < meas.size(); ++j)
      if (!r[j].f.values.empty()) rmse[meas[j]] = r[j].f.rmse_after;
  }
  std::stable_sort(meas.begin(), meas.end(),
                   [&](std::size_t a, std::size_t b) { return rmse[a] < rmse[b]; });
  meas.resize(std::min(meas.size(), 2 * opt_.refits));
  // The counterparts on unmeasured nodes (`Entry::proxy`) wait for their proxies' refits.
  std::vector<std::size_t> first, beside;
  for (std::size_t i = 0; i < chosen_.size(); ++i) {
    if (!model_side(chosen_[i]) && std::find(meas.begin(), meas.end(), i) == meas.end()) continue;
    (chosen_[i].proxy.empty() ? first : beside).push_back(i);
  }
  refit_batch(first, recal, ranged, rep);
  // Both ΔBICs are against the declared model, and the joint fit has the recalibration's params
  // and its own: their difference is the proxy's ΔBIC against the recalibration.
  const std::vector<std::size_t> second =
      beside_gaining(chosen_, beside, res_, first, res_[recal].f.delta_bic, opt_.refits);
  refit_batch(second, recal, ranged, rep);
}

void Selection::refit_batch(const std::vector<std::size_t>& todo, std::size_t recal,
                            const std::vector<double>& ranged, DiagnosisReport& rep) {
  std::vector<Entry> entries;
  for (std::size_t i : todo)
    entries.push_back(joint_entry(chosen_[i], recal, ranged));
  std::vector<Evaluated> jres = engine_.evaluate_all(entries, engine_.declared(), true);
  rep.refitted += todo.size();
  for (std::size_t j = 0; j < todo.size(); ++j) {
    if (jres[j].f.values.empty()) continue; // the joint fit failed: keep the own refit, if any
    const std::size_t i = todo[j];
    note_joint(jres[j].f, recal);
    res_[i] = std::move(jres[j]);
    chosen_[i] = std::move(entries[j]);
  }
}

Entry Selection::joint_entry(const Entry& e, std::size_t recal, const std::vector<double>& ranged) {
  joints_.push_back(std::make_unique<Joint>(e.h, e.c, chosen_[recal].h, chosen_[recal].c));
  Entry je = e;
  je.h = joints_.back().get();
  je.c = joints_.back()->candidate(ranged);
  return je;
}

void Selection::note_joint(Finding& f, std::size_t recal) const {
  f.evidence +=
      (f.evidence.empty() ? "" : "; ") + fmt::format("refitted jointly with the ranged params ({})",
                                                     fmt::join(chosen_[recal].c.names, ", "));
}

} // namespace thermnet::detail
