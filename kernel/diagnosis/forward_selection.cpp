// The greedy forward selection: the best finding is applied, and the next one is searched for
// given it -- the screen repeated on the extended model plus every other significant candidate,
// refitted on top of it -- until nothing is significant, the error is at the noise floor or the
// report is full. Each step re-estimates the selected findings together and stands only if that
// keeps its gain on held-out data.

#include "kernel/diagnosis/selection.hpp"

#include "kernel/calibration/least_squares.hpp"

#include <algorithm>
#include <memory>
#include <set>
#include <utility>

namespace thermnet::detail {

namespace {

/// A base whose held-out residuals are those of its own validation folds (each fold's data
/// predicted by a fit without them), as a candidate's are: the next step compares like with like.
Base with_holdout(Base base, StoredResiduals holdout_r) {
  if (holdout_r.size() != base.holdout_r.size()) return base;
  base.holdout_r = std::move(holdout_r);
  base.sse_test = sum_of_squares(base.holdout_r);
  return base;
}

} // namespace

Base Selection::select_forward(DiagnosisReport& rep, Base& last) {
  std::vector<Applied> applied;
  Base best = engine_.declared();
  if (!first_.empty()) {
    const std::size_t b = first_.front();
    applied.push_back({chosen_[b].h, chosen_[b].c, res_[b].f.values});
    rep.findings.push_back(res_[b].f);
    add_rivals(rep.findings.back(), b, chosen_, res_);
    best = engine_.make_base(applied);
  }
  Base base = first_.empty() ? best : with_holdout(best, res_[first_.front()].holdout_r);
  // The first refits' residuals are not read again (the later steps compare their own refits, and
  // the report takes only their findings): released, as each step's own are when it ends (two
  // vectors of the measured points per refit, most of a large data file's memory).
  for (Evaluated& e : res_) {
    std::vector<StoredResiduals>().swap(e.r);
    StoredResiduals().swap(e.holdout_r);
    std::vector<double>().swap(e.holdout_rho);
  }
  // The ranged params are not recalibrated again once a finding has recalibrated them.
  const bool params_applied = !applied.empty() && applied.front().h->recalibrates();
  while (!applied.empty() && rep.findings.size() < opt_.top && !base.at_floor) {
    std::vector<Entry> next;
    try {
      next = next_entries(base, applied, params_applied);
    } catch (const std::exception&) {
      break;
    }
    std::vector<Evaluated> nres = evaluate_next(next, base, rep);
    judge(nres, base);
    merge_mechanisms(next, nres);
    rep.refitted += rerank_jointly(applied, base, next, nres);
    for (const auto& e : nres)
      if (!e.f.values.empty() && !e.f.significant) rep.rejected.push_back(e.f);
    const auto order = ranked(nres);
    if (order.empty()) break;
    const std::size_t b = order.front();
    add_rivals(nres[b].f, b, next, nres);
    applied.push_back({next[b].h, next[b].c, nres[b].f.values});
    StoredResiduals holdout_r;
    if (!reestimate(applied, nres[b].f, rep, holdout_r)) break;
    base = with_holdout(engine_.make_base(applied), std::move(holdout_r));
  }
  last = std::move(base); // (not copied: a base holds every measured point twice over)
  return best;
}

std::vector<Evaluated> Selection::evaluate_next(const std::vector<Entry>& next, const Base& base,
                                                DiagnosisReport& rep) const {
  // As in the joint refits, a counterpart on unmeasured nodes is refitted only beside a proxy
  // whose refit on top of the findings beats them by the information criterion, among the best of
  // its kind (B72 of bench/diagnosis.md: two fifths of the step's simulations went to counterparts
  // beside proxies that gain nothing once the first finding is applied).
  std::vector<std::size_t> first, beside;
  for (std::size_t i = 0; i < next.size(); ++i)
    (next[i].proxy.empty() ? first : beside).push_back(i);
  std::vector<Evaluated> nres(next.size());
  const auto refit = [&](const std::vector<std::size_t>& todo) {
    std::vector<Entry> entries;
    for (std::size_t i : todo)
      entries.push_back(next[i]);
    std::vector<Evaluated> r = engine_.evaluate_all(entries, base);
    for (std::size_t k = 0; k < todo.size(); ++k)
      nres[todo[k]] = std::move(r[k]);
    rep.refitted += todo.size();
  };
  refit(first);
  refit(beside_gaining(next, beside, nres, first, 0.0, opt_.refits));
  return nres;
}

std::size_t Selection::rerank_jointly(const std::vector<Applied>& applied, const Base& base,
                                      const std::vector<Entry>& next,
                                      std::vector<Evaluated>& nres) const {
  // A candidate fitted on top of the applied findings meets them (and the ranged params they
  // recalibrated) at values fitted without it, which favours proxies of what they absorbed, and
  // may gain little alone where it would with them refitted (a solar gain's size once the house's
  // envelope and capacity move with it). The best sites by that refit, significant or not, are
  // refitted together with every applied finding (values and ranged params free) and judged and
  // ranked on that joint fit; the others are not selected at this step.
  std::vector<std::size_t> top;
  std::set<std::string> sites;
  for (std::size_t i : ranked(nres, false)) {
    if (top.size() >= opt_.refits) break;
    if (sites.insert(site(nres[i].f.candidate)).second) top.push_back(i);
  }
  // A link to an unmeasured node tied to a boundary and the link to that boundary differ little
  // on top of findings whose params absorbed part of the effect: both are refitted jointly.
  for (std::size_t k = 0, n = top.size(); k < n; ++k)
    for (std::size_t j : boundary_exchanges(next, engine_.evidence(), next[top[k]].c))
      if (!nres[j].f.values.empty() && sites.insert(site(nres[j].f.candidate)).second)
        top.push_back(j);
  std::vector<std::unique_ptr<Compose>> composed;
  std::vector<Entry> entries;
  for (std::size_t i : top) {
    std::vector<Applied> parts = applied;
    parts.push_back({next[i].h, next[i].c, nres[i].f.values});
    composed.push_back(std::make_unique<Compose>(std::move(parts)));
    Entry e = next[i];
    e.h = composed.back().get();
    e.c = composed.back()->candidate();
    entries.push_back(std::move(e));
  }
  std::vector<Evaluated> jres = engine_.evaluate_all(entries, engine_.declared(), true);
  std::vector<char> keep(nres.size(), 0);
  const double na = static_cast<double>(engine_.points());
  for (std::size_t k = 0; k < top.size(); ++k) {
    Evaluated& e = nres[top[k]];
    const Finding& j = jres[k].f;
    if (j.values.empty()) continue;
    keep[top[k]] = 1;
    e.f.rmse_after = j.rmse_after, e.f.r2_after = j.r2_after;
    e.f.validation_rmse_after = j.validation_rmse_after;
    e.f.validation_r2_after = j.validation_r2_after;
    e.f.delta_bic = engine_.delta_bic(j.rmse_after * j.rmse_after * na, base.sse_all,
                                      static_cast<double>(e.f.candidate.start.size()));
    e.r = std::move(jres[k].r);
    e.holdout_r = std::move(jres[k].holdout_r);
    e.holdout_rho = std::move(jres[k].holdout_rho);
    e.holdout_sse = jres[k].holdout_sse;
    e.degenerate = jres[k].degenerate; // (at the joint fit's values: a share may reach its bound)
  }
  judge(nres, base);
  for (std::size_t i = 0; i < nres.size(); ++i)
    nres[i].f.significant = nres[i].f.significant && keep[i];
  return top.size();
}

std::vector<Entry> Selection::next_entries(const Base& base, const std::vector<Applied>& applied,
                                           bool params_applied) const {
  const Evidence ev = engine_.evidence_at(base);
  Screened s = screen(ev);
  std::vector<Entry> next;
  for (auto& e : s.others)
    if (!(e.own_h->recalibrates() && params_applied)) next.push_back(std::move(e));
  for (auto& e : shortlisted(s.side, ev, opt_.refits, nullptr))
    next.push_back(std::move(e));
  for (std::size_t i : first_) {
    if (chosen_[i].own_h->recalibrates() && params_applied) continue;
    Entry e;
    e.h = e.own_h = chosen_[i].own_h;
    e.c = e.own = chosen_[i].own;
    if (std::none_of(next.begin(), next.end(),
                     [&](const Entry& x) { return same_candidate(x.c, e.c); }))
      next.push_back(std::move(e));
  }
  // Not again, and not a second rerouting of an element a finding has rerouted (a heater's
  // power moved onto a mass cannot be moved again from where the model had it).
  next.erase(std::remove_if(next.begin(), next.end(),
                            [&](const Entry& x) {
                              return std::any_of(
                                  applied.begin(), applied.end(), [&](const Applied& a) {
                                    return same_candidate(a.c, x.c) ||
                                           (a.h->reroutes() && x.own_h->reroutes() &&
                                            !x.c.element.empty() && a.c.element == x.c.element);
                                  });
                            }),
             next.end());
  return next;
}

bool Selection::reestimate(std::vector<Applied>& applied, Finding f, DiagnosisReport& rep,
                           StoredResiduals& holdout_r) const {
  // The selected findings are re-estimated together (the earlier ones were fitted without this
  // one): their values, and this step's gain, come from the joint refit.
  const Compose all(applied);
  Entry je;
  je.h = &all;
  je.c = all.candidate();
  Evaluated joint = engine_.evaluate(je, engine_.declared(), true);
  rep.refitted += 1;
  if (joint.f.values.empty()) return false;
  rep.findings.push_back(f);
  std::vector<std::string> mechanisms;
  for (const auto& a : applied)
    mechanisms.push_back(a.c.mechanism);
  redecide_mechanisms(applied, all, joint, rep);
  f = rep.findings.back();
  rep.findings.pop_back();
  // The step stands only if the joint refit keeps its gain on held-out data.
  if (joint.f.validation_rmse_after >
      rep.findings.back().validation_rmse_after + 0.1 * engine_.evidence().noise_floor) {
    applied.pop_back();
    return false;
  }
  for (std::size_t i = 0; i < applied.size(); ++i)
    applied[i].p = all.slice(joint.f.values, i); // the variants share the layout
  f.values = applied.back().p;
  f.rmse_after = joint.f.rmse_after;
  f.r2_after = joint.f.r2_after;
  f.validation_rmse_before = rep.findings.back().validation_rmse_after;
  f.validation_r2_before = rep.findings.back().validation_r2_after;
  f.validation_rmse_after = joint.f.validation_rmse_after;
  f.validation_r2_after = joint.f.validation_r2_after;
  // An earlier finding keeps the values its own step fitted, with which its stated gain was
  // reached (and which --write writes, whatever --top is); only one whose mechanism was decided
  // again takes the joint values of its new mechanism.
  const Evidence& ev = engine_.evidence();
  for (std::size_t i = 0; i < rep.findings.size(); ++i)
    if (applied[i].c.mechanism != mechanisms[i]) {
      rep.findings[i].values = applied[i].p;
      write_extension(rep.findings[i], *applied[i].h, applied[i].c, applied[i].p, ev);
    }
  write_extension(f, *applied.back().h, applied.back().c, applied.back().p, ev);
  rep.findings.push_back(std::move(f));
  holdout_r = std::move(joint.holdout_r);
  return true;
}

void Selection::redecide_mechanisms(std::vector<Applied>& applied, const Compose& all,
                                    Evaluated& joint, DiagnosisReport& rep) const {
  // A finding whose mechanism was not told apart is decided again given the other findings: the
  // joint refit with its other mechanism is compared with this one (rep.findings holds the step's
  // new finding last, alongside `applied`).
  for (std::size_t i = 0; i < applied.size(); ++i) {
    Finding& fi = rep.findings[i];
    // (a finding refitted with the ranged params keeps its mechanism: the variant would not be)
    if (fi.mechanism_identified || applied[i].h->recalibrates()) continue;
    auto other = std::find_if(side_.begin(), side_.end(), [&](const Entry& x) {
      return site(x.c) == site(fi.candidate) && x.c.mechanism != fi.candidate.mechanism;
    });
    if (other == side_.end()) continue;
    std::vector<Applied> variant = applied;
    for (std::size_t j = 0; j < variant.size(); ++j)
      variant[j].p = all.slice(joint.f.values, j);
    variant[i] = {other->own_h, other->own, other->own.start};
    const Compose vall(variant);
    Entry ve;
    ve.h = &vall;
    ve.c = vall.candidate();
    const Evaluated v = engine_.evaluate(ve, engine_.declared(), true);
    rep.refitted += 1;
    if (v.f.values.empty()) continue;
    const FitComparison cmp = compare_fits({joint.r, joint.holdout_sse}, {v.r, v.holdout_sse},
                                           engine_.evidence().noise_floor);
    // The note compares the two joint refits; the finding's own gain stays its step's.
    Finding now = fi, alt = fi;
    now.rmse_after = joint.f.rmse_after, now.validation_rmse_after = joint.f.validation_rmse_after;
    alt.candidate = variant[i].c;
    alt.rmse_after = v.f.rmse_after, alt.validation_rmse_after = v.f.validation_rmse_after;
    Finding& keep = cmp.first_better ? now : alt;
    note_mechanism(keep, cmp.first_better ? alt : now, cmp, other->own_h->mechanisms());
    if (!cmp.first_better) fi.evidence = keep.candidate.evidence;
    fi.candidate = keep.candidate, fi.mechanism_note = keep.mechanism_note;
    fi.mechanism_identified = keep.mechanism_identified, fi.mechanism_z = keep.mechanism_z;
    if (!cmp.first_better) {
      applied[i] = variant[i];
      joint = v;
    }
  }
}

} // namespace thermnet::detail
