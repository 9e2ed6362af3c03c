// The diagnosis engine's decisions: which candidates the screen's shortlist refits (by site, per
// node, widened when the best comes from its edge), the joint refit with the ranged params,
// significance, mechanism honesty, ranking, and the greedy forward selection of findings.

#include "kernel/diagnosis/engine.hpp"

#include "kernel/core/parallel.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

namespace thermnet::detail {

namespace {

/// Where a candidate acts (a link's two mechanisms are one site).
std::string site(const Candidate& c) {
  return fmt::format("{}|{}|{}", c.kind, fmt::join(c.nodes, ","), c.element);
}

/// Distinct sites in the order of the entries (the screen's order).
std::vector<std::string> site_order(const std::vector<Entry>& side) {
  std::vector<std::string> order;
  std::set<std::string> seen;
  for (const auto& e : side)
    if (e.c.screen > 0 && seen.insert(site(e.c)).second) order.push_back(site(e.c));
  return order;
}

/// True when a candidate is refitted as a model extension and compared by its screen score.
bool model_side(const Entry& e) {
  return !e.c.measurement_side && !e.own_h->recalibrates();
}

/// Records on `keep` how its mechanism compared with the other one (`drop`); `mechanisms` are its
/// kind's, in order.
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

} // namespace

std::vector<Entry> Engine::propose(const Evidence& ev) const {
  std::vector<Entry> out;
  const auto& elements = ev_.cases.front().spec.elements;
  for (const auto& h : hyps_)
    for (auto& c : h->propose(ev)) {
      // An element added by an applied finding is not a site of the model's own.
      if (!c.element.empty() &&
          std::none_of(elements.begin(), elements.end(),
                       [&](const lang::ElementSpec& e) { return e.name == c.element; }))
        continue;
      Entry e;
      e.h = e.own_h = h.get();
      e.own = c;
      e.c = std::move(c);
      out.push_back(std::move(e));
    }
  return out;
}

std::vector<std::size_t> Engine::shortlist(const std::vector<Entry>& side, const Evidence& ev,
                                           std::size_t sites) const {
  // `side` is sorted by falling screen score. The shortlist holds, by site: the `sites` best, the
  // best of each kind, and -- since the regression ranks sites of every node together, where a
  // node with a large unexplained flow may be out-scored by many proxies elsewhere -- the two best
  // sites of each of the three nodes with the largest unexplained heat flow.
  const std::vector<std::string> order = site_order(side);
  std::set<std::string> wanted(order.begin(),
                               order.begin() + static_cast<long>(std::min(sites, order.size())));
  std::set<std::string> kinds;
  for (const auto& e : side)
    if (e.c.screen > 0 && kinds.insert(e.c.kind).second) wanted.insert(site(e.c));
  std::map<int, double> flow; // node -> sum of (q / C)^2
  for (const auto& ce : ev.cases)
    for (int node : ce.rows) {
      const double C = ce.spec.nodes[static_cast<std::size_t>(node)].C;
      for (const auto& q : ce.q)
        if (std::isfinite(q[static_cast<std::size_t>(node)]))
          flow[node] +=
              q[static_cast<std::size_t>(node)] * q[static_cast<std::size_t>(node)] / (C * C);
    }
  std::vector<std::pair<double, int>> nodes;
  for (const auto& [node, ss] : flow)
    nodes.emplace_back(-ss, node);
  std::sort(nodes.begin(), nodes.end());
  for (std::size_t i = 0; i < nodes.size() && i < 3; ++i) {
    const std::string& name =
        ev.cases.front().spec.nodes[static_cast<std::size_t>(nodes[i].second)].name;
    std::set<std::string> of_node;
    for (const auto& e : side)
      if (e.c.screen > 0 && of_node.size() < 2 &&
          std::find(e.c.nodes.begin(), e.c.nodes.end(), name) != e.c.nodes.end())
        of_node.insert(site(e.c));
    wanted.insert(of_node.begin(), of_node.end());
  }
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < side.size(); ++i)
    if (side[i].c.screen > 0 && wanted.count(site(side[i].c)) != 0) idx.push_back(i);
  return idx;
}

std::vector<Evaluated> Engine::evaluate_all(const std::vector<Entry>& entries, const Base& base,
                                            bool joint) const {
  std::vector<Evaluated> res(entries.size());
  parallel_for(entries.size(), opt_.threads,
               [&](std::size_t i) { res[i] = evaluate(entries[i], base, joint); });
  return res;
}

void Engine::judge(std::vector<Evaluated>& res) const {
  // Better by the information criterion, not worse on held-out data, a real drop of the error.
  const double nf = ev_.noise_floor;
  for (auto& e : res) {
    Finding& f = e.f;
    f.significant = !f.values.empty() && f.delta_bic < -10.0 &&
                    f.validation_rmse_after <= f.validation_rmse_before + 0.1 * nf &&
                    f.rmse_after < 0.97 * f.rmse_before;
  }
}

void Engine::merge_mechanisms(const std::vector<Entry>& entries,
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
          compare_fits({a.r, a.holdout_sse}, {b.r, b.holdout_sse}, ev_.noise_floor);
      Evaluated& keep = cmp.first_better ? a : b;
      Evaluated& drop = cmp.first_better ? b : a;
      note_mechanism(keep.f, drop.f, cmp, entries[i].own_h->mechanisms());
      drop.f.values.clear(); // merged into keep
    }
}

double Engine::score(const Finding& f) const {
  // Predictive error on held-out data plus the information criterion on all data.
  const double na = static_cast<double>(n_all_), nt = std::max(1.0, static_cast<double>(n_test_));
  const double all2 = std::max(f.rmse_after * f.rmse_after, 1e-300);
  const double hold2 = std::max(f.validation_rmse_after * f.validation_rmse_after, 1e-300);
  return nt * std::log(hold2) + na * std::log(all2) +
         static_cast<double>(f.values.size()) * std::log(na);
}

std::vector<std::size_t> Engine::ranked(const std::vector<Evaluated>& res) const {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < res.size(); ++i)
    if (!res[i].f.values.empty() && res[i].f.significant) idx.push_back(i);
  std::stable_sort(idx.begin(), idx.end(),
                   [&](std::size_t a, std::size_t b) { return score(res[a].f) < score(res[b].f); });
  return idx;
}

DiagnosisReport Engine::run() {
  const auto t0 = std::chrono::steady_clock::now();
  collect_evidence();
  for (const auto& name : HypothesisRegistry::global().names())
    hyps_.push_back(HypothesisRegistry::global().find(name)->create());
  DiagnosisReport rep;
  rep.model = model_.path();
  for (const auto& ce : ev_.cases)
    rep.cases.push_back(ce.name);
  rep.noise_floor = ev_.noise_floor;
  rep.validation = loco_ ? "leave_one_case_out" : "held_back_time";
  rep.folds = folds();
  base0_ = make_base({});
  std::vector<double> r;
  residuals(base0_.sims, Part{}, r);
  n_all_ = r.size();
  n_test_ = 0;
  for (std::size_t f = 0; f < folds(); ++f) {
    residuals(base0_.sims, Part{Part::test, f}, r);
    n_test_ += r.size();
  }
  rep.baseline = base0_.metrics;
  rep.at_noise_floor = base0_.at_floor;
  if (rep.at_noise_floor) {
    add_curves(rep, base0_);
    rep.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rep;
  }

  // 1. The screen: every plugin proposes; the shortlist of model-side candidates is refitted
  // together with every measurement-side candidate and `parameter`.
  std::vector<Entry> side, chosen;
  for (auto& e : propose(ev_)) {
    ++rep.screened;
    (model_side(e) ? side : chosen).push_back(std::move(e));
  }
  std::stable_sort(side.begin(), side.end(),
                   [](const Entry& a, const Entry& b) { return a.c.screen > b.c.screen; });
  std::size_t sites = opt_.refits;
  std::set<std::size_t> taken;
  auto add_shortlist = [&](const std::vector<Entry>& from, const std::vector<std::size_t>& idx,
                           std::set<std::size_t>* seen) {
    std::vector<Entry> fresh;
    for (std::size_t i : idx)
      if (!seen || seen->insert(i).second) fresh.push_back(from[i]);
    return fresh;
  };
  for (auto& e : add_shortlist(side, shortlist(side, ev_, sites), &taken))
    chosen.push_back(std::move(e));
  std::vector<Evaluated> res = evaluate_all(chosen, base0_);
  // Widening: when the best refitted site sits in the last third of the shortlist's sites, the
  // screen's order is a poor guide here: the next sites are refitted too (at most twice).
  const std::vector<std::string> order = site_order(side);
  for (int round = 0; round < 2; ++round) {
    judge(res);
    const auto best = ranked(res);
    std::size_t pos = 0;
    for (std::size_t i : best)
      if (model_side(chosen[i])) {
        pos = static_cast<std::size_t>(std::find(order.begin(), order.end(), site(chosen[i].c)) -
                                       order.begin());
        break;
      }
    if (best.empty() || pos < sites - sites / 3 || pos >= order.size() || sites >= order.size())
      break;
    sites += opt_.refits;
    std::vector<Entry> more = add_shortlist(side, shortlist(side, ev_, sites), &taken);
    std::vector<Evaluated> mres = evaluate_all(more, base0_);
    for (std::size_t i = 0; i < more.size(); ++i) {
      chosen.push_back(std::move(more[i]));
      res.push_back(std::move(mres[i]));
    }
  }
  rep.refitted = chosen.size();

  // 2. Joint refit: when recalibrating the ranged params alone is significant (the `parameter`
  // candidate beats the baseline by the information criterion), the model's params are wrong too,
  // so a candidate's own parameter fitted at the declared values says little. Every refitted
  // model-side candidate is then refitted again with its parameter and every ranged param together
  // (bounded, started at the recalibrated values) and compared on that footing: the joint result
  // replaces its own-parameter refit, and its extra parameter must also beat the recalibration
  // alone by the BIC margin (otherwise the recalibration explains it: `parameter`).
  std::vector<std::unique_ptr<Joint>> joints;
  std::vector<double> vs_parameter(chosen.size(), -std::numeric_limits<double>::infinity());
  std::size_t ipar = chosen.size();
  for (std::size_t i = 0; i < chosen.size(); ++i)
    if (chosen[i].own_h->recalibrates()) ipar = i;
  if (ipar < chosen.size() && !res[ipar].f.values.empty() && res[ipar].f.delta_bic < -10.0) {
    const std::vector<double> ranged = res[ipar].f.values;
    // The screen is repeated at the recalibrated params (the unexplained heat flows change with
    // them): twice as many sites (a weak guide at wrong params, many near-equal sites after).
    try {
      const Base recal = make_base({Applied{chosen[ipar].h, chosen[ipar].c, ranged}});
      std::vector<Entry> side2;
      for (auto& e : propose(evidence_at(recal)))
        if (model_side(e)) side2.push_back(std::move(e));
      std::stable_sort(side2.begin(), side2.end(),
                       [](const Entry& a, const Entry& b) { return a.c.screen > b.c.screen; });
      for (auto& e :
           add_shortlist(side2, shortlist(side2, evidence_at(recal), 2 * opt_.refits), nullptr))
        if (std::none_of(chosen.begin(), chosen.end(),
                         [&](const Entry& x) { return same_candidate(x.c, e.c); })) {
          chosen.push_back(std::move(e));
          res.emplace_back(); // no own-parameter refit: evaluated jointly only
          vs_parameter.push_back(-std::numeric_limits<double>::infinity());
        }
    } catch (const std::exception&) {
      // the recalibrated screen failed: the declared-value shortlist only
    }
    std::vector<std::size_t> todo;
    std::vector<Entry> jentries;
    for (std::size_t i = 0; i < chosen.size(); ++i) {
      if (!model_side(chosen[i])) continue;
      joints.push_back(
          std::make_unique<Joint>(chosen[i].h, chosen[i].c, chosen[ipar].h, chosen[ipar].c));
      todo.push_back(i);
      Entry je = chosen[i];
      je.h = joints.back().get();
      je.c = joints.back()->candidate(ranged);
      jentries.push_back(std::move(je));
    }
    std::vector<Evaluated> jres = evaluate_all(jentries, base0_, true);
    rep.refitted += todo.size();
    const double na = static_cast<double>(n_all_);
    const double floor2 = std::max(ev_.noise_floor * ev_.noise_floor, 1e-12) * 1e-4;
    const double sse_par = res[ipar].f.rmse_after * res[ipar].f.rmse_after * na;
    for (std::size_t j = 0; j < todo.size(); ++j) {
      if (jres[j].f.values.empty()) continue; // the joint fit failed: keep the own refit
      const std::size_t i = todo[j];
      const double sse = jres[j].f.rmse_after * jres[j].f.rmse_after * na;
      const double extra = static_cast<double>(chosen[i].own.start.size());
      vs_parameter[i] =
          na * std::log((sse + floor2 * na) / (sse_par + floor2 * na)) + extra * std::log(na);
      jres[j].f.evidence += (jres[j].f.evidence.empty() ? "" : "; ") +
                            fmt::format("refitted jointly with the ranged params ({})",
                                        fmt::join(chosen[ipar].c.names, ", "));
      res[i] = std::move(jres[j]);
      chosen[i] = std::move(jentries[j]);
    }
  }
  judge(res);
  for (std::size_t i = 0; i < res.size(); ++i)
    res[i].f.significant = res[i].f.significant && vs_parameter[i] < -10.0;
  merge_mechanisms(chosen, res);
  const std::vector<std::size_t> first = ranked(res);

  // 3. Greedy forward selection: the best finding is applied, and the next one is searched for
  // given it -- the screen repeated on the extended model plus every other significant candidate,
  // refitted on top of it -- until nothing is significant or the error is at the noise floor.
  // Candidates that were significant only as proxies of a selected finding become alternatives.
  std::vector<Applied> applied;
  Base best_base = base0_;
  if (!first.empty()) {
    const std::size_t b = first.front();
    applied.push_back({chosen[b].h, chosen[b].c, res[b].f.values});
    rep.findings.push_back(res[b].f);
    best_base = make_base(applied);
  }
  Base base = best_base;
  // The ranged params are not recalibrated again once a finding has recalibrated them.
  const bool params_applied = !applied.empty() && applied.front().h->recalibrates();
  while (!applied.empty() && rep.findings.size() < opt_.top && !base.at_floor) {
    std::vector<Entry> next, side3;
    try {
      for (auto& e : propose(evidence_at(base))) {
        if (e.own_h->recalibrates() && params_applied) continue;
        (model_side(e) ? side3 : next).push_back(std::move(e));
      }
    } catch (const std::exception&) {
      break;
    }
    std::stable_sort(side3.begin(), side3.end(),
                     [](const Entry& a, const Entry& b) { return a.c.screen > b.c.screen; });
    for (auto& e : add_shortlist(side3, shortlist(side3, evidence_at(base), opt_.refits), nullptr))
      next.push_back(std::move(e));
    for (std::size_t i : first) {
      Entry e;
      e.h = e.own_h = chosen[i].own_h;
      e.c = e.own = chosen[i].own;
      if (std::none_of(next.begin(), next.end(),
                       [&](const Entry& x) { return same_candidate(x.c, e.c); }))
        next.push_back(std::move(e));
    }
    next.erase(std::remove_if(next.begin(), next.end(),
                              [&](const Entry& x) {
                                return std::any_of(
                                    applied.begin(), applied.end(),
                                    [&](const Applied& a) { return same_candidate(a.c, x.c); });
                              }),
               next.end());
    std::vector<Evaluated> nres = evaluate_all(next, base);
    rep.refitted += next.size();
    judge(nres);
    merge_mechanisms(next, nres);
    const auto order2 = ranked(nres);
    if (order2.empty()) break;
    const std::size_t b = order2.front();
    applied.push_back({next[b].h, next[b].c, nres[b].f.values});
    Finding f = nres[b].f;
    // The selected findings are re-estimated together (the earlier ones were fitted without this
    // one): their values, and this step's gain, come from the joint refit.
    const Compose all(applied);
    Entry je;
    je.h = &all;
    je.c = all.candidate();
    Evaluated joint = evaluate(je, base0_, true);
    rep.refitted += 1;
    if (joint.f.values.empty()) break;
    // A link whose mechanism was not told apart is decided again given the other findings: the
    // joint refit with its other mechanism is compared with this one.
    rep.findings.push_back(f);
    for (std::size_t i = 0; i < applied.size(); ++i) {
      Finding& fi = rep.findings[i];
      // (a finding refitted with the ranged params keeps its mechanism: the variant would not be)
      if (fi.mechanism_identified || applied[i].h->recalibrates()) continue;
      auto other = std::find_if(side.begin(), side.end(), [&](const Entry& x) {
        return site(x.c) == site(fi.candidate) && x.c.mechanism != fi.candidate.mechanism;
      });
      if (other == side.end()) continue;
      std::vector<Applied> variant = applied;
      for (std::size_t j = 0; j < variant.size(); ++j)
        variant[j].p = all.slice(joint.f.values, j);
      variant[i] = {other->own_h, other->own, other->own.start};
      const Compose vall(variant);
      Entry ve;
      ve.h = &vall;
      ve.c = vall.candidate();
      const Evaluated v = evaluate(ve, base0_, true);
      rep.refitted += 1;
      if (v.f.values.empty()) continue;
      const FitComparison cmp =
          compare_fits({joint.r, joint.holdout_sse}, {v.r, v.holdout_sse}, ev_.noise_floor);
      // The note compares the two joint refits; the finding's own gain stays its step's.
      Finding now = fi, alt = fi;
      now.rmse_after = joint.f.rmse_after,
      now.validation_rmse_after = joint.f.validation_rmse_after;
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
    f = rep.findings.back();
    rep.findings.pop_back();
    // The step stands only if the joint refit keeps its gain on held-out data.
    if (joint.f.validation_rmse_after >
        rep.findings.back().validation_rmse_after + 0.1 * ev_.noise_floor) {
      applied.pop_back();
      break;
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
    for (std::size_t i = 0; i < rep.findings.size(); ++i) {
      rep.findings[i].values = applied[i].p;
      write_extension(rep.findings[i], *applied[i].h, applied[i].c, applied[i].p, ev_);
    }
    write_extension(f, *applied.back().h, applied.back().c, applied.back().p, ev_);
    rep.findings.push_back(std::move(f));
    base = make_base(applied);
  }
  for (std::size_t i = 0; i < rep.findings.size(); ++i) {
    Finding& f = rep.findings[i];
    f.rank = static_cast<int>(i + 1);
    std::string words = trend_words(rep.baseline, f.candidate.nodes);
    if (!words.empty() && i == 0) f.evidence += (f.evidence.empty() ? "" : "; ") + words;
  }
  for (std::size_t i : first)
    if (std::none_of(rep.findings.begin(), rep.findings.end(), [&](const Finding& f) {
          return site(f.candidate) == site(res[i].f.candidate);
        }))
      if (rep.alternatives.size() < opt_.top) rep.alternatives.push_back(res[i].f);
  for (auto& e : res)
    if (!e.f.values.empty() && !e.f.significant) rep.rejected.push_back(std::move(e.f));
  add_curves(rep, best_base);
  rep.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

void Engine::add_curves(DiagnosisReport& rep, const Base& after) const {
  // Measured, baseline and the best finding, per case.
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
    rep.curves.push_back(std::move(cv));
  }
}

} // namespace thermnet::detail
