// select_by_likelihood(): forward selection of findings by likelihood-ratio tests of maximum
// likelihood fits of the one-step-ahead predictions.

#include "kernel/diagnosis/prediction_selection.hpp"

#include "kernel/calibration/calibration_problem.hpp"
#include "kernel/diagnosis/composites.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <map>
#include <set>

namespace thermnet::detail {
namespace {

constexpr double kAlpha = 0.05;         // significance level of a step's tests (before Bonferroni)
constexpr double kResolvedError = 1e-3; // K: a simulation error no thermal test resolves
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The candidates of a step are fitted briefly (this many quasi-Newton iterations at most, stopped
// when one gains less than this share of the likelihood), the best kFullFits of them fully.
constexpr int kBriefIterations = 20;
constexpr double kBriefTolerance = 1e-6;
constexpr std::size_t kFullFits = 2;
// A full fit stops when an iteration gains less than this share of 1 + |ln L| (3e-4 on the
// building's ln L of 3000): far below the differences a likelihood-ratio test resolves, and a
// quarter fewer likelihoods than the default tolerance on the building's selection.
constexpr double kFullTolerance = 1e-7;
// A candidate's structure holds the one it extends (its added state's share or capacity at a
// bound), so its refit reaches that likelihood or nearly: a likelihood ratio below minus this
// (ln L lower by half a unit, thousands of times the fits' tolerance) is a refit that failed.
constexpr double kFailedRatio = 1.0;

/// A structure of the selection: the declared model, the findings applied so far and optionally a
/// free candidate, with the ranged params and the applied findings' values free.
struct Structure {
  const std::vector<Applied>* applied = nullptr;
  const Hypothesis* h = nullptr; // free candidate's hypothesis (null: none)
  const Candidate* c = nullptr;
};

class Selector {
public:
  Selector(const Engine& engine, const DiagnosisOptions& opt)
      : engine_(engine), opt_(opt), ev_(engine.evidence()), calib_(*ev_.model, case_names(ev_)) {
    for (const auto& name : HypothesisRegistry::global().names())
      hyps_.push_back(HypothesisRegistry::global().find(name)->create());
    for (const auto& ce : ev_.cases)
      data_.push_back(ce.measured);
  }

  Base run(DiagnosisReport& rep) {
    PredictionSummary sum;
    sum.initial_sd = opt_.initial_sd;
    sum.alpha = kAlpha;
    std::vector<Applied> applied;
    Fitted base = fit({&applied, nullptr, nullptr}, {});
    if (!base.fit.ok)
      throw DiagnosisError("the likelihood of the declared model cannot be evaluated (the Kalman "
                           "filter fails at the declared values)");
    sum.declared = base.summary;
    sum.whiteness_before = base.whiteness;
    // A model that already simulates the data within their noise, or within a millikelvin (what
    // no thermal test resolves: the data's own integration or rounding error), has nothing left
    // to explain, however sharp a likelihood-ratio test on such tiny residuals would be.
    const double declared_rmse = engine_.declared().metrics.rmse;
    const bool nothing_to_explain = engine_.declared().at_floor || declared_rmse <= kResolvedError;
    if (nothing_to_explain)
      sum.notes.push_back(fmt::format(
          "the declared model simulates the data within {:.3g} K ({}): no structure was tested",
          declared_rmse, engine_.declared().at_floor ? "their measurement noise" : "below 1 mK"));
    for (std::size_t step = 0; step < opt_.top && !nothing_to_explain; ++step) {
      const std::size_t offset = calib_.dimension() + applied_count(applied);
      const Evidence ev = step == 0 ? ev_ : engine_.evidence_at(engine_.make_base(applied));
      const std::vector<std::pair<const Hypothesis*, Candidate>> cands = shortlist(ev, applied);
      if (cands.empty()) break;
      const auto wall0 = std::chrono::steady_clock::now();
      const std::clock_t cpu0 = std::clock();
      RefitBatch batch;
      batch.base_findings = applied.size();
      batch.refits = cands.size();
      const std::string stage = fmt::format("likelihood step {}: fitting the candidates", step + 1);
      // Every candidate is fitted briefly from the model it extends; the few with the highest
      // likelihood then fully, from both starts (most candidates gain nothing, and a brief fit's
      // likelihood is a lower bound of its maximum: a candidate left at it is never made
      // significant by it).
      std::vector<Fitted> fits;
      for (const auto& [h, c] : cands) {
        if (opt_.progress) opt_.progress({stage, fits.size(), cands.size()});
        fits.push_back(fit({&applied, h, &c}, base.by_name, Effort::brief));
        batch.likelihoods += fits.back().fit.evaluations;
        ++sum.tested;
      }
      std::vector<std::size_t> order(cands.size());
      for (std::size_t i = 0; i < order.size(); ++i)
        order[i] = i;
      const auto ll = [&](std::size_t i) {
        return fits[i].fit.ok ? fits[i].fit.log_likelihood
                              : -std::numeric_limits<double>::infinity();
      };
      std::stable_sort(order.begin(), order.end(),
                       [&](std::size_t a, std::size_t b) { return ll(a) > ll(b); });
      for (std::size_t k = 0; k < std::min(kFullFits, order.size()); ++k) {
        const std::size_t i = order[k];
        if (!fits[i].fit.ok) break;
        Fitted full = fit({&applied, cands[i].first, &cands[i].second}, base.by_name);
        batch.likelihoods += full.fit.evaluations;
        if (full.fit.ok && full.fit.log_likelihood >= fits[i].fit.log_likelihood)
          fits[i] = std::move(full);
      }
      if (opt_.progress) opt_.progress({stage, fits.size(), cands.size()});
      const auto close_batch = [&] {
        batch.wall_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
        batch.cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
        rep.batches.push_back(batch);
      };
      const double threshold = kAlpha / static_cast<double>(cands.size());
      std::size_t best = cands.size();
      std::vector<Finding> findings(cands.size());
      for (std::size_t i = 0; i < cands.size(); ++i) {
        Finding& f = findings[i];
        f.candidate = cands[i].second;
        f.given = static_cast<int>(applied.size());
        if (!fits[i].fit.ok) continue;
        LikelihoodTest t;
        t.before = base.summary;
        t.after = fits[i].summary;
        t.ratio = likelihood_ratio(base.fit.log_likelihood, base.fit.parameters,
                                   fits[i].fit.log_likelihood, fits[i].fit.parameters);

        t.threshold = threshold;
        describe(f, fits[i], base, t, *cands[i].first, ev, offset);
        if (t.ratio.statistic < 0)
          f.evidence += "; the refit stayed below the likelihood of the model it extends (a "
                        "local maximum of the candidate's likelihood)";
        f.fit_failed = t.ratio.statistic < -kFailedRatio;
        f.significant = t.ratio.df > 0 && t.ratio.p_value < threshold;
        f.likelihood = t;
        if (f.significant && (best == cands.size() || fits[i].fit.bic < fits[best].fit.bic))
          best = i;
      }
      for (std::size_t i = 0; i < cands.size(); ++i)
        if (i != best && fits[i].fit.ok) rep.rejected.push_back(findings[i]);
      rep.refitted += cands.size();
      rep.screened += cands.size();
      if (best == cands.size()) {
        close_batch();
        break;
      }
      // Standard errors for the finding taken only: a Hessian costs 2 n^2 likelihoods, more than
      // the fit itself, and a rejected candidate's are not reported.
      const std::size_t fitted = fits[best].fit.evaluations;
      standard_errors({&applied, cands[best].first, &cands[best].second}, fits[best]);
      batch.likelihoods += fits[best].fit.evaluations - fitted;
      close_batch();
      Finding f = findings[best];
      f.std_errors.assign(fits[best].fit.std_errors.begin() + static_cast<long>(offset),
                          fits[best].fit.std_errors.begin() +
                              static_cast<long>(offset + own_of(f)));
      f.rank = static_cast<int>(rep.findings.size()) + 1;
      const std::size_t own = cands[best].second.names.size();
      const std::vector<double>& th = fits[best].fit.theta;
      const std::vector<double> values(th.begin() + static_cast<long>(offset),
                                       th.begin() + static_cast<long>(offset + own));
      rep.findings.push_back(f);
      // The findings applied before are refitted with it: their values move to the joint fit.
      auto at = th.begin() + static_cast<long>(calib_.dimension());
      for (auto& a : applied) {
        a.p.assign(at, at + static_cast<long>(a.c.names.size()));
        at += static_cast<long>(a.c.names.size());
      }
      applied.push_back({cands[best].first, cands[best].second, values});
      base = std::move(fits[best]);
    }
    sum.final_fit = base.summary;
    sum.whiteness_after = base.whiteness;
    sum.notes.push_back(
        "sensor offsets and gains are not tested by the likelihood (the output-error "
        "criterion tests them); a sensor's lag is");
    sum.notes.push_back("the ranged params are refitted with every structure (no separate "
                        "`parameter` finding)");
    rep.prediction = std::move(sum);
    Base selected = engine_.make_base(applied);
    // (here, while the hypotheses the findings name are alive: the curves simulate their steps)
    rep.curves = engine_.curves(selected, selected);
    return selected;
  }

private:
  struct Fitted {
    PredictionFit fit;
    LikelihoodFit summary;
    std::vector<SeriesWhiteness> whiteness;
    double rmse = kNaN, r2 = kNaN;         // the simulation's, at the fitted values
    std::map<std::string, double> by_name; // every fitted parameter
  };

  static std::vector<std::string> case_names(const Evidence& ev) {
    std::vector<std::string> n;
    for (const auto& c : ev.cases)
      n.push_back(c.name);
    return n;
  }

  static std::size_t own_of(const Finding& f) { return f.candidate.names.size(); }

  // Parameters of the applied findings, all together.
  static std::size_t applied_count(const std::vector<Applied>& applied) {
    std::size_t n = 0;
    for (const auto& a : applied)
      n += a.c.names.size();
    return n;
  }

  // The case networks of a structure at x = ranged params, every applied finding's (refitted with
  // them, so that each structure contains the one it extends), then the free candidate's own.
  SpecMaker maker(Structure s) const {
    const std::size_t nr = calib_.dimension();
    return [this, s, nr](std::size_t ci, const std::vector<double>& x) {
      std::vector<Applied> applied = *s.applied;
      auto at = x.begin() + static_cast<long>(nr);
      for (auto& a : applied) {
        a.p.assign(at, at + static_cast<long>(a.c.names.size()));
        at += static_cast<long>(a.c.names.size());
      }
      const std::vector<double> ranged(x.begin(), x.begin() + static_cast<long>(nr));
      const std::vector<double> own(at, x.end());
      const Stack st(&applied, s.h, s.c);
      const Candidate none;
      lang::ParamValues pv = calib_.values(ranged);
      for (auto& [k, v] : st.overrides(none, own))
        pv.insert_or_assign(k, v);
      lang::NetworkSpec spec = ev_.model->instantiate(ev_.cases[ci].name, pv);
      st.extend(none, own, spec);
      return spec;
    };
  }

  // A candidate's parameter i in the fit of the structure (stable across steps: finding k's).
  static PredictionParam candidate_param(const Candidate& c, std::size_t j, std::size_t finding,
                                         double start) {
    PredictionParam q;
    q.name = fmt::format("finding{}.{}.{}", finding, c.kind, c.names[j]);
    const double lo = c.lo[j], hi = c.hi[j];
    q.box = {lo, hi, lo > 0 && hi / lo > 10 ? ParamScale::log : ParamScale::linear};
    q.start = std::clamp(start, lo, hi);
    return q;
  }

  // How hard a fit tries: briefly from one start, or fully from two.
  enum class Effort { brief, full };

  // The prediction problem of a structure.
  PredictionProblem problem(Structure s, Effort effort = Effort::full) const {
    std::vector<PredictionParam> structural;
    for (const auto& p : calib_.params()) {
      PredictionParam q;
      q.name = p.name;
      q.box = {*p.lo, *p.hi, *p.lo > 0 ? ParamScale::log : ParamScale::linear};
      q.start = p.value;
      structural.push_back(q);
    }
    for (std::size_t k = 0; k < s.applied->size(); ++k) {
      const Applied& a = (*s.applied)[k];
      for (std::size_t j = 0; j < a.c.names.size(); ++j)
        structural.push_back(candidate_param(a.c, j, k + 1, a.p[j]));
    }
    if (s.c)
      for (std::size_t j = 0; j < s.c->names.size(); ++j)
        structural.push_back(candidate_param(*s.c, j, s.applied->size() + 1, s.c->start[j]));
    PredictionSettings settings;
    settings.initial_sd = opt_.initial_sd;
    settings.local_linearisation = true;
    settings.threads = opt_.threads;
    if (effort == Effort::brief) {
      settings.max_iterations = kBriefIterations;
      settings.ftol = kBriefTolerance;
    } else {
      settings.ftol = kFullTolerance;
    }
    return PredictionProblem(structural, maker(s), case_names(ev_), data_, settings);
  }

  // The standard errors of a fitted structure (from its likelihood's Hessian).
  void standard_errors(Structure s, Fitted& f) const {
    try {
      add_standard_errors(problem(s), f.fit);
    } catch (const std::exception&) {
      f.fit.std_errors.assign(f.fit.theta.size(), kNaN);
    }
  }

  // Maximum-likelihood fit of a structure, started from `warm` (values by name) where known,
  // without standard errors. A brief fit moves the candidate's own params and the noise from
  // `warm`; a full one everything, from `warm` and from the deterministic stage.
  Fitted fit(Structure s, const std::map<std::string, double>& warm, Effort effort = Effort::full) {
    Fitted out;
    try {
      const SpecMaker make = maker(s);
      const PredictionProblem pp = problem(s, effort);
      const auto start_at = [&pp](const std::map<std::string, double>& values) {
        std::vector<double> start = pp.start();
        for (std::size_t k = 0; k < pp.params().size(); ++k)
          if (auto it = values.find(pp.params()[k].name); it != values.end())
            start[k] = std::clamp(it->second, pp.params()[k].box.lo, pp.params()[k].box.hi);
        return start;
      };
      const std::vector<double> start = start_at(warm);
      if (effort == Effort::brief) {
        out.fit = brief_fit(s, pp, start);
      } else {
        // The declared structure from its declared values (the deterministic stage first); a
        // candidate from the fitted model it extends, its own parameters at the kind's start.
        out.fit = fit_prediction(pp, start, false, true);
        if (!warm.empty()) {
          // A candidate's likelihood has local maxima: from the fitted model it extends (its
          // noise already absorbing what the candidate explains) the search can stall at a bound,
          // from the deterministic stage it can end below the nested model (the house's heater
          // mass). Both are tried; the higher maximum is kept.
          const PredictionFit direct = fit_prediction(pp, start, false, false);
          if (direct.ok && (!out.fit.ok || direct.log_likelihood > out.fit.log_likelihood)) {
            const std::size_t det = out.fit.evaluations;
            out.fit = direct;
            out.fit.evaluations += det;
          } else if (direct.ok) {
            out.fit.evaluations += direct.evaluations;
          }
        }
      }
      if (!out.fit.ok) return out;
      describe_fit(pp, make, out);
    } catch (const std::exception&) {
      out.fit.ok = false;
    }
    return out;
  }

  // A candidate's own params and the noise fitted from `start` (every other value held there):
  // a lower bound of the structure's likelihood, in a few iterations. The fit is returned in the
  // layout of the whole structure `pp` (its parameter count that of the whole structure, as the
  // likelihood-ratio test of the full fit counts them).
  PredictionFit brief_fit(Structure s, const PredictionProblem& pp,
                          const std::vector<double>& start) const {
    const std::size_t own = s.c ? s.c->names.size() : 0;
    const std::size_t held = pp.structural() - own;
    const std::vector<double> fixed(start.begin(), start.begin() + static_cast<long>(held));
    const std::vector<PredictionParam> free(pp.params().begin() + static_cast<long>(held),
                                            pp.params().begin() +
                                                static_cast<long>(pp.structural()));
    const SpecMaker whole = maker(s);
    const SpecMaker make = [whole, fixed](std::size_t ci, const std::vector<double>& x) {
      std::vector<double> all = fixed;
      all.insert(all.end(), x.begin(), x.end());
      return whole(ci, all);
    };
    const PredictionProblem part(free, make, case_names(ev_), data_, pp.settings());
    std::vector<double> part_start(start.begin() + static_cast<long>(held), start.end());
    if (part_start.size() != part.params().size()) // (the same network: the same noise params)
      throw std::logic_error("a brief fit's problem differs from its structure's");
    PredictionFit r = fit_prediction(part, part_start, false, false);
    std::vector<double> theta = fixed;
    theta.insert(theta.end(), r.theta.begin(), r.theta.end());
    r.theta = std::move(theta);
    r.std_errors.assign(r.theta.size(), kNaN);
    r.parameters = pp.params().size();
    const double k = static_cast<double>(r.parameters);
    r.aic = -2 * r.log_likelihood + 2 * k;
    r.bic = -2 * r.log_likelihood + k * std::log(static_cast<double>(r.points));
    return r;
  }

  // The summary, whiteness and simulation error of a fit of pp.
  void describe_fit(const PredictionProblem& pp, const SpecMaker& make, Fitted& out) const {
    {
      for (std::size_t k = 0; k < pp.params().size(); ++k) {
        out.by_name[pp.params()[k].name] = out.fit.theta[k];
        out.summary.values.emplace_back(pp.params()[k].name, out.fit.theta[k]);
      }
      const auto innovations = pp.innovations(out.fit.theta);
      out.whiteness = test_innovations(innovations);
      out.summary.one_step_rmse = one_step_rmse(innovations);
      out.summary.log_likelihood = out.fit.log_likelihood;
      out.summary.parameters = out.fit.parameters;
      out.summary.aic = out.fit.aic;
      out.summary.bic = out.fit.bic;
      simulation_error(pp, make, out);
    }
  }

  // The simulation's RMSE and R² at the fitted structural values (the output-error fields).
  void simulation_error(const PredictionProblem& pp, const SpecMaker& make, Fitted& f) const {
    const std::vector<double> x(f.fit.theta.begin(),
                                f.fit.theta.begin() + static_cast<long>(pp.structural()));
    double sse = 0.0, sum = 0.0, sum2 = 0.0, first = 0.0; // sums about the first value: data
    std::size_t n = 0;                                    // that do not vary give sst = 0
    for (std::size_t c = 0; c < ev_.cases.size(); ++c) {
      const MeasuredData& d = ev_.cases[c].measured;
      const auto sims = simulate_case(make(c, x), d.times);
      for (const auto& s : d.series)
        for (std::size_t k = 0; k < d.times.size(); ++k) {
          const double m = s.values[k];
          if (std::isnan(m)) continue;
          const double r = sims[k][static_cast<std::size_t>(s.node_index)] - m;
          sse += r * r;
          if (n++ == 0) first = m;
          sum += m - first;
          sum2 += (m - first) * (m - first);
        }
    }
    if (n == 0) return;
    const double dn = static_cast<double>(n);
    const double sst = sum2 - sum * sum / dn;
    f.rmse = std::sqrt(sse / dn);
    f.r2 = sst > 0 ? 1 - sse / sst : kNaN;
  }

  // Model-side candidates by falling screen score: `refits` sites, the best of each kind, and
  // every candidate of a kind the screen cannot score (unmeasured nodes) when it has few.
  std::vector<std::pair<const Hypothesis*, Candidate>>
  shortlist(const Evidence& ev, const std::vector<Applied>& applied) const {
    std::vector<std::pair<const Hypothesis*, Candidate>> all;
    const auto& declared = ev_.cases.front().spec;
    for (const auto& h : hyps_) {
      if (h->recalibrates()) continue;
      for (auto& c : h->propose_for_likelihood(ev)) {
        // A sensor's lag is a state the filter observes through the sensor; an offset or a gain
        // is left to the output-error criterion.
        if (c.measurement_side && c.kind != "sensor_lag") continue;
        // An element an applied finding added (a split's heater) is not a site of the model's
        // own; a node it added (the envelope a split may heat) is, except for its capacity,
        // already one of the finding's free params.
        if (!on_model_sites(c, declared,
                            c.kind == "capacity_error" ? AddedNodes::refused : AddedNodes::allowed))
          continue;
        if (!c.start_T.empty()) c = with_start_share(c);
        bool taken = false;
        for (const auto& a : applied)
          taken |= same_candidate(a.c, c);
        if (!taken) all.emplace_back(h.get(), std::move(c));
      }
    }
    std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
      return a.second.screen > b.second.screen;
    });
    std::vector<std::pair<const Hypothesis*, Candidate>> out;
    std::set<std::string> sites, kinds, scored;
    std::map<std::string, std::size_t> unobserved, unscored;
    for (const auto& [h, c] : all) {
      if (c.unobserved) ++unobserved[c.kind];
      if (c.screen > 0) scored.insert(c.kind);
    }
    auto site_of = [](const Candidate& c) {
      return fmt::format("{}|{}|{}", c.kind, fmt::join(c.nodes, ","), c.element);
    };
    for (const auto& [h, c] : all) {
      const std::string site = site_of(c);
      // A kind the screen scored nowhere (no screen rows: inputs that change at every sample,
      // as a building's weather does) is tested by its first candidates in proposal order.
      const bool keep =
          (c.screen > 0 &&
           (sites.size() < opt_.refits || sites.count(site) || !kinds.count(c.kind))) ||
          (c.unobserved && unobserved[c.kind] <= opt_.refits) ||
          (!c.unobserved && !scored.count(c.kind) && unscored[c.kind]++ < opt_.refits);
      if (!keep) continue;
      if (c.screen > 0) sites.insert(site);
      kinds.insert(c.kind);
      out.emplace_back(h, c);
    }
    return out;
  }

  void describe(Finding& f, const Fitted& after, const Fitted& before, const LikelihoodTest& t,
                const Hypothesis& h, const Evidence& ev, std::size_t offset) const {
    const std::size_t own = f.candidate.names.size();
    f.values.assign(after.fit.theta.begin() + static_cast<long>(offset),
                    after.fit.theta.begin() + static_cast<long>(offset + own));
    f.std_errors.assign(after.fit.std_errors.begin() + static_cast<long>(offset),
                        after.fit.std_errors.begin() + static_cast<long>(offset + own));
    f.rmse_before = before.rmse;
    f.rmse_after = after.rmse;
    f.r2_before = before.r2;
    f.r2_after = after.r2;
    f.validation_rmse_before = f.validation_rmse_after = kNaN;
    f.validation_r2_before = f.validation_r2_after = kNaN;
    f.delta_bic = after.fit.bic - before.fit.bic;
    f.evidence = fmt::format(
        "log-likelihood {:.6g} -> {:.6g} with {} more parameter{}: likelihood ratio {:.4g}, "
        "p = {:.3g} (chi-square, {} df; significant below {:.3g}); one-step RMS {:.4g} -> {:.4g} "
        "K",
        t.before.log_likelihood, t.after.log_likelihood, t.ratio.df, t.ratio.df == 1 ? "" : "s",
        t.ratio.statistic, t.ratio.p_value, t.ratio.df, t.threshold, t.before.one_step_rmse,
        t.after.one_step_rmse);
    try {
      write_extension(f, h, f.candidate, f.values, ev);
    } catch (const std::exception& e) {
      // A candidate on a node an applied finding added has no statement against the declared
      // model (its kind writes against the declarations).
      f.statement = fmt::format("# {} [{}] cannot be written against the declared model ({})",
                                f.candidate.kind, fmt::join(f.candidate.nodes, ", "), e.what());
    }
  }

  const Engine& engine_;
  const DiagnosisOptions& opt_;
  const Evidence& ev_;
  CalibrationProblem calib_;
  std::vector<MeasuredData> data_;
  std::vector<std::unique_ptr<Hypothesis>> hyps_;
};

} // namespace

Base select_by_likelihood(const Engine& engine, const DiagnosisOptions& options,
                          DiagnosisReport& rep) {
  Selector s(engine, options);
  return s.run(rep);
}

} // namespace thermnet::detail
