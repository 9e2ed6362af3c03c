#include "app/diagnosis_html.hpp"

#include "app/diagnosis_output.hpp"
#include "app/report_page.hpp"
#include "kernel/diagnosis/hypothesis.hpp"
#include "kernel/diagnosis/report.hpp"
#include "plot/html_page.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet::app {
namespace {

using plot::Align;
using plot::HtmlPage;
using plot::HtmlTable;

/// Samples of the worst window (as the diagnosis measures window_rmse).
constexpr std::size_t kWindow = 10;

/// Where a node's error is largest over kWindow consecutive measured samples.
struct Window {
  double rmse = 0.0;     ///< its RMS error, K
  std::string case_name; ///< the case
  double from = NAN;     ///< first sample's time, s
  double to = NAN;       ///< last sample's time, s
};

Window worst_window(const std::vector<DiagnosisReport::Curves>& curves, const std::string& node) {
  Window best;
  for (const auto& cv : curves) {
    const auto m = cv.measured.find(node);
    const auto s = cv.before.find(node);
    if (m == cv.measured.end() || s == cv.before.end()) continue;
    std::vector<std::size_t> at;
    for (std::size_t k = 0; k < m->second.size() && k < s->second.size() && k < cv.times.size();
         ++k)
      if (!std::isnan(m->second[k])) at.push_back(k);
    if (at.empty()) continue;
    const std::size_t w = std::min(kWindow, at.size());
    double sum = 0.0;
    auto e2 = [&](std::size_t j) {
      const double e = s->second[at[j]] - m->second[at[j]];
      return e * e;
    };
    for (std::size_t j = 0; j < at.size(); ++j) {
      sum += e2(j);
      if (j >= w) sum -= e2(j - w);
      if (j + 1 < w) continue;
      const double rms = std::sqrt(std::max(sum, 0.0) / static_cast<double>(w));
      if (rms > best.rmse) best = {rms, cv.case_name, cv.times[at[j + 1 - w]], cv.times[at[j]]};
    }
  }
  return best;
}

std::string r2_words(double r2) {
  return std::isnan(r2) ? std::string("undefined") : fmt::format("{:.4f}", r2);
}

std::string what_of(const Candidate& c) {
  std::string s = c.kind;
  if (!c.mechanism.empty()) s += " (" + c.mechanism + ")";
  s += " at " + fmt::format("{}", fmt::join(c.nodes, ", "));
  if (!c.element.empty()) s += ", element " + c.element;
  return s;
}

std::string validation_words(const DiagnosisReport& r) {
  if (r.validation == "leave_one_case_out")
    return fmt::format("leave one case out: each of the {} cases predicted by a fit to the others",
                       r.folds);
  if (r.validation == "case_folds")
    return fmt::format("{} folds of whole cases, each predicted by a fit to the other folds",
                       r.folds);
  if (r.validation == "held_back_time")
    return fmt::format("{} equal stretches of the case, each predicted by a fit to the others",
                       r.folds);
  if (r.validation == "cases_and_time")
    return fmt::format("{} folds: whole cases, and stretches of {}", r.folds,
                       fmt::join(r.split_cases, ", "));
  return r.validation.empty() ? std::string("—") : r.validation;
}

std::string values_words(const std::vector<std::string>& names, const std::vector<double>& v) {
  std::vector<std::string> parts;
  for (std::size_t k = 0; k < names.size() && k < v.size(); ++k)
    parts.push_back(fmt::format("{} = {}", names[k], page_number(v[k])));
  return fmt::format("{}", fmt::join(parts, ", "));
}

void add_run(HtmlPage& page, const DiagnosisReport& r, const std::vector<NamedInput>& inputs) {
  page.open_section("run", "Run");
  add_run_facts(
      page, r.model, inputs,
      {{"criterion", r.criterion == "prediction"
                         ? "prediction: likelihood of a Kalman filter's one-step-ahead "
                           "predictions, likelihood-ratio tests"
                         : "output error: simulation residuals, gains checked on held-out data"},
       {"cases", fmt::format("{}: {}", r.cases.size(), fmt::join(r.cases, ", "))},
       {"validation", validation_words(r)},
       {"measurement noise",
        fmt::format("about {} K (estimated from the data)", page_number(r.noise_floor, 3))},
       {"practical floor (--min-gain)", page_number(r.min_gain, 3) + " K"},
       {"candidates",
        fmt::format("{} screened, {} refitted by simulation", r.screened, r.refitted)},
       {"wall time", fmt::format("{:.1f} s", r.wall_s)}});
  page.close_section();
}

void add_summary(HtmlPage& page, const DiagnosisReport& r) {
  page.open_section("summary", "Summary");
  page.paragraph(fmt::format("The model as declared misses the measurements by an RMSE of {} K "
                             "(R² {}); the measurement noise is about {} K.",
                             page_number(r.baseline.rmse, 3), r2_words(r.baseline.r2),
                             page_number(r.noise_floor, 3)),
                 "lead");
  if (r.findings.empty()) {
    page.paragraph(r.at_noise_floor
                       ? "No finding: the remaining error is at the measurement noise floor."
                       : fmt::format("No significant finding: no candidate extension predicts "
                                     "held-out data better beyond chance and lowers the error by "
                                     "at least {} K somewhere (--min-gain).",
                                     page_number(r.min_gain, 3)));
  } else {
    std::vector<std::string> items;
    for (const auto& f : r.findings)
      items.push_back(fmt::format(
          "{}. {}: RMSE {} → {} K, held out {} → {} K", f.rank, what_of(f.candidate),
          page_number(f.rmse_before, 3), page_number(f.rmse_after, 3),
          page_number(f.validation_rmse_before, 3), page_number(f.validation_rmse_after, 3)));
    page.paragraph(fmt::format("{} finding{}, ranked, each given the ones above:",
                               r.findings.size(), r.findings.size() == 1 ? "" : "s"));
    page.list(items);
  }
  if (r.structural.remains)
    page.paragraph(fmt::format("Structural error remains: RMSE {} K after the findings against a "
                               "noise of about {} K; no finding kind explains it (see the "
                               "residual diagnostics).",
                               page_number(r.structural.rmse, 3), page_number(r.noise_floor, 3)),
                   "note");
  page.close_section();
}

void add_baseline(HtmlPage& page, const DiagnosisReport& r) {
  page.open_section("baseline", "Baseline: the model as declared");
  std::vector<std::pair<std::string, NodeMetrics>> nodes(r.baseline.nodes.begin(),
                                                         r.baseline.nodes.end());
  std::stable_sort(nodes.begin(), nodes.end(),
                   [](const auto& a, const auto& b) { return a.second.rmse > b.second.rmse; });
  HtmlTable t;
  t.caption = "Per measured node, every case (worst first)";
  t.head = {"node",
            "RMSE [K]",
            "bias [K]",
            "largest error [K]",
            "at (case, t [s])",
            "worst window RMSE [K]",
            "worst window (case, t [s])",
            "points"};
  t.align = {Align::left, Align::right, Align::right, Align::right,
             Align::left, Align::right, Align::left,  Align::right};
  for (const auto& [name, m] : nodes) {
    const Window w = worst_window(r.curves, name);
    t.rows.push_back(
        {name, page_number(m.rmse, 3), page_number(m.bias, 3), page_number(m.max_error, 3),
         fmt::format("{}, {}", m.max_error_case, page_number(m.max_error_time, 6)),
         page_number(m.window_rmse, 3),
         w.case_name.empty() ? std::string("—")
                             : fmt::format("{}, {} – {}", w.case_name, page_number(w.from, 6),
                                           page_number(w.to, 6)),
         std::to_string(m.points)});
  }
  page.table(t);
  page.paragraph(fmt::format("The worst window is the stretch of {} consecutive measured samples "
                             "with the largest RMS error (an error confined to a short span, which "
                             "the RMSE of the whole series dilutes). Errors are simulated minus "
                             "measured.",
                             kWindow),
                 "note");
  if (r.baseline.cases.size() > 1) {
    HtmlTable c;
    c.caption = "RMSE per case [K]";
    c.head = {"case"};
    c.align = {Align::left};
    for (const auto& [name, m] : nodes) {
      c.head.push_back(name);
      c.align.push_back(Align::right);
    }
    for (const auto& [cname, per] : r.baseline.cases) {
      std::vector<std::string> row{cname};
      for (const auto& [name, m] : nodes) {
        const auto it = per.find(name);
        row.push_back(it == per.end() ? "—" : page_number(it->second.rmse, 3));
      }
      c.rows.push_back(std::move(row));
    }
    page.table(c);
  }
  auto fig = diagnosis_figure(r, "", 3, false);
  fig.columns = r.curves.size() > 1 ? 2 : 1;
  fig.panel_height = r.curves.size() > 1 ? 300 : 380;
  page.figure(std::move(fig),
              "Measured (markers) and simulated (lines) temperatures of the worst nodes (by RMSE), "
              "one panel per case, the model as declared.",
              "baseline");
  page.close_section();
}

void add_finding(HtmlPage& page, const Finding& f, const DiagnosisReport& r) {
  const Candidate& c = f.candidate;
  page.open_section(fmt::format("finding-{}", f.rank),
                    fmt::format("Finding {}: {}", f.rank, what_of(c)),
                    {{"class", "finding"},
                     {"data-rank", std::to_string(f.rank)},
                     {"data-kind", c.kind},
                     {"data-nodes", fmt::format("{}", fmt::join(c.nodes, ","))}});
  std::vector<std::pair<std::string, std::string>> facts = {{"kind", c.kind}};
  if (const auto* plugin = HypothesisRegistry::global().find(c.kind)) {
    if (!plugin->doc.empty()) facts.emplace_back("what it is", plugin->doc);
    if (!plugin->fitted.empty()) facts.emplace_back("what is fitted", plugin->fitted);
  }
  facts.emplace_back(
      "where", fmt::format("node{} {}", c.nodes.size() == 1 ? "" : "s", fmt::join(c.nodes, ", ")) +
                   (c.element.empty() ? "" : ", element " + c.element));
  if (!c.mechanism.empty())
    facts.emplace_back("mechanism", c.mechanism +
                                        (f.mechanism_identified ? "" : " (not identified)") +
                                        (f.mechanism_note.empty() ? "" : ": " + f.mechanism_note));
  facts.emplace_back("given",
                     f.given == 0
                         ? std::string("the model as declared")
                         : fmt::format("finding{} 1{} applied", f.given > 1 ? "s" : "",
                                       f.given > 1 ? fmt::format("–{}", f.given) : std::string()));
  facts.emplace_back("evidence", f.evidence);
  page.facts(facts);

  HtmlTable gain;
  gain.caption = "Gain";
  gain.head = {"data", "RMSE before [K]", "RMSE after [K]", "R² before", "R² after"};
  gain.align = {Align::left, Align::right, Align::right, Align::right, Align::right};
  gain.rows.push_back({"in sample (all data, fitted)", page_number(f.rmse_before),
                       page_number(f.rmse_after), r2_words(f.r2_before), r2_words(f.r2_after)});
  gain.rows.push_back({"held out (" + validation_words(r) + ")",
                       page_number(f.validation_rmse_before), page_number(f.validation_rmse_after),
                       r2_words(f.validation_r2_before), r2_words(f.validation_r2_after)});
  page.table(gain);

  HtmlTable sig;
  sig.caption = "Significance";
  sig.head = {"test", "value", "reads"};
  sig.align = {Align::left, Align::right, Align::left};
  // (the likelihood criterion tests by the likelihood ratio alone: the output-error criterion's
  // held-out z and local gain are not computed for its findings, and not shown as zeros)
  if (!f.likelihood)
    sig.rows.push_back({"held-out gain over its reference fit",
                        "z = " + page_number(f.holdout_z, 3),
                        "how many standard errors the held-out predictions improve"});
  sig.rows.push_back({"ΔBIC (after − before)", page_number(f.delta_bic, 4),
                      f.delta_bic < 0 ? "negative: the extension pays for its parameters"
                                      : "not negative: the extension does not pay for its "
                                        "parameters by BIC"});
  if (!f.likelihood && std::isfinite(f.window_gain))
    sig.rows.push_back({"largest local gain (10 samples)", page_number(f.window_gain, 3) + " K",
                        fmt::format("practical floor {} K", page_number(r.min_gain, 3))});
  if (f.likelihood) {
    const LikelihoodTest& t = *f.likelihood;
    sig.rows.push_back({"likelihood ratio",
                        fmt::format("{} ({} df)", page_number(t.ratio.statistic, 4), t.ratio.df),
                        fmt::format("p = {} (significant below {})",
                                    page_number(t.ratio.p_value, 3), page_number(t.threshold, 3))});
  }
  page.table(sig);

  if (!r.curves.empty() && r.curves.front().steps.size() >= static_cast<std::size_t>(f.rank)) {
    const auto k = static_cast<std::size_t>(f.rank);
    auto fig = diagnosis_figure(r, "", 3, true, k - 1, k);
    fig.columns = r.curves.size() > 1 ? 2 : 1;
    fig.panel_height = r.curves.size() > 1 ? 260 : 320;
    page.figure(std::move(fig),
                f.rank == 1
                    ? std::string("This finding's own step: measured (markers), the model as "
                                  "declared (solid) and with this finding (dashed), worst "
                                  "nodes, one panel per case.")
                    : fmt::format("This finding's own step: measured (markers), the model "
                                  "with finding{} 1{} (solid) and with this one too "
                                  "(dashed), worst nodes, one panel per case.",
                                  f.rank > 2 ? "s" : "",
                                  f.rank > 2 ? fmt::format("–{}", f.rank - 1) : std::string()),
                fmt::format("finding-{}-step", f.rank));
  }

  HtmlTable params;
  params.caption = "Fitted parameters (SI)";
  params.head = {"parameter", "fitted", "standard error", "95 % interval (±1.96 SE)", "note"};
  params.align = {Align::left, Align::right, Align::right, Align::right, Align::left};
  for (std::size_t k = 0; k < c.names.size() && k < f.values.size(); ++k) {
    const double v = f.values[k];
    const double se = k < f.std_errors.size() ? f.std_errors[k] : NAN;
    std::string note;
    if (auto b = f.at_bounds.find(c.names[k]); b != f.at_bounds.end())
      note = "on its " + b->second + " bound: a limit, not an estimate";
    else if (!std::isfinite(se))
      note = "no standard error: the fit's curvature does not determine it (or, with other "
             "parameters on bounds, it cannot be separated from them)";
    params.rows.push_back({c.names[k], page_number(v, 5), page_number(se, 3),
                           std::isfinite(se) ? fmt::format("{} … {}", page_number(v - 1.96 * se),
                                                           page_number(v + 1.96 * se))
                                             : std::string("—"),
                           note});
  }
  for (const auto& [name, value] : f.param_rewrites)
    params.rows.push_back(
        {name, page_number(value, 5), "—", "—", "a ranged param of the model, refitted jointly"});
  if (!params.rows.empty()) page.table(params);

  if (!f.rivals.empty()) {
    HtmlTable amb;
    amb.caption = "Ambiguity set: the candidates that fit as well";
    amb.head = {"candidate", "fitted values (SI)", "RMSE [K]", "held-out RMSE [K]",
                "z (this finding better by)"};
    amb.align = {Align::left, Align::left, Align::right, Align::right, Align::right};
    amb.rows.push_back({what_of(c) + " (this finding)", values_words(c.names, f.values),
                        page_number(f.rmse_after), page_number(f.validation_rmse_after), "—"});
    for (const auto& rv : f.rivals)
      amb.rows.push_back({what_of(rv.candidate), values_words(rv.candidate.names, rv.values),
                          page_number(rv.rmse_after), page_number(rv.validation_rmse_after),
                          page_number(rv.z, 3)});
    page.table(amb);
    if (!f.separate_by.empty()) page.paragraph("To separate them: " + f.separate_by, "note");
  } else {
    page.paragraph("No other candidate fits as well (the ambiguity set is this finding alone).",
                   "note");
  }
  page.code(finding_lines(f),
            f.rank == 1 ? "The lines that add it to the model (--write writes these)"
                        : "The lines that add it to the model (given the findings above; "
                          "--write writes the first finding only)",
            {{"class", "model-lines"}, {"data-rank", std::to_string(f.rank)}});
  page.close_section();
}

void add_findings(HtmlPage& page, const DiagnosisReport& r) {
  page.open_section("findings", "Findings");
  if (r.findings.empty())
    page.paragraph(r.at_noise_floor ? "None: the error is at the measurement noise floor."
                                    : "None was significant.");
  for (const auto& f : r.findings)
    add_finding(page, f, r);
  if (!r.findings.empty()) {
    page.open_section("before-after", "Before and after");
    auto fig = diagnosis_figure(r, "", 3, true, 0, r.findings.size());
    fig.columns = r.curves.size() > 1 ? 2 : 1;
    fig.panel_height = r.curves.size() > 1 ? 300 : 380;
    page.figure(
        std::move(fig),
        fmt::format("Measured (markers), the model as declared (solid) and with {} "
                    "applied (dashed), worst nodes, one panel per case.{}",
                    r.findings.size() == 1 ? std::string("the finding")
                                           : fmt::format("findings 1–{}", r.findings.size()),
                    r.findings.size() == 1 ? "" : " Each finding's own step is in its gain table."),
        "before-after");
    page.close_section();
  }
  if (!r.alternatives.empty()) {
    page.open_section("alternatives", "Also significant alone, explained by the findings above");
    HtmlTable t;
    t.head = {"candidate", "fitted values (SI)", "RMSE after [K]", "held-out RMSE after [K]", "z",
              "ΔBIC"};
    t.align = {Align::left, Align::left, Align::right, Align::right, Align::right, Align::right};
    for (const auto& f : r.alternatives)
      t.rows.push_back({what_of(f.candidate), values_words(f.candidate.names, f.values),
                        page_number(f.rmse_after), page_number(f.validation_rmse_after),
                        f.likelihood ? std::string("—") : page_number(f.holdout_z, 3),
                        page_number(f.delta_bic, 4)});
    page.table(t);
    page.close_section();
  }
  if (!r.rejected.empty()) {
    page.open_section("rejected", "Refitted but not significant");
    HtmlTable t;
    t.head = {"candidate", "fitted values (SI)", "RMSE after [K]", "held-out RMSE after [K]", "z",
              "ΔBIC"};
    t.align = {Align::left, Align::left, Align::right, Align::right, Align::right, Align::right};
    for (const auto& f : r.rejected)
      t.rows.push_back({what_of(f.candidate) + (f.fit_failed ? " (fit failed: not a measure of "
                                                               "its gain)"
                                                             : ""),
                        values_words(f.candidate.names, f.values), page_number(f.rmse_after),
                        page_number(f.validation_rmse_after),
                        f.likelihood ? std::string("—") : page_number(f.holdout_z, 3),
                        page_number(f.delta_bic, 4)});
    page.table(t);
    page.close_section();
  }
  page.close_section();
}

void add_prediction(HtmlPage& page, const DiagnosisReport& r) {
  const PredictionSummary& p = *r.prediction;
  page.open_section("likelihood", "Likelihood (prediction criterion)");
  HtmlTable t;
  t.head = {"model", "log-likelihood", "parameters", "AIC", "BIC", "one-step RMSE [K]"};
  t.align = {Align::left, Align::right, Align::right, Align::right, Align::right, Align::right};
  auto row = [&](const std::string& name, const LikelihoodFit& f) {
    t.rows.push_back({name, page_number(f.log_likelihood, 7), std::to_string(f.parameters),
                      page_number(f.aic, 7), page_number(f.bic, 7),
                      page_number(f.one_step_rmse, 3)});
  };
  row("as declared (refitted)", p.declared);
  row("with the findings", p.final_fit);
  page.table(t);
  page.paragraph(fmt::format("{} candidate models fitted; each step's tests at a level of {} "
                             "(Bonferroni-corrected); initial states' standard deviation {} K.",
                             p.tested, page_number(p.alpha, 3), page_number(p.initial_sd, 3)),
                 "note");
  if (!p.notes.empty()) page.list(p.notes);
  page.close_section();
}

void add_residuals(HtmlPage& page, const DiagnosisReport& r) {
  page.open_section("residuals", "Residual diagnostics");
  if (r.prediction) {
    const bool found = !r.findings.empty();
    page.paragraph(fmt::format(
        "The innovations (one-step-ahead prediction errors) of the model {}: white innovations "
        "mean the model and its noise describe the dynamics; structure left in them shows as "
        "autocorrelation beyond the band and a cumulated periodogram that leaves its band.",
        found ? "with the findings" : "as declared"));
    add_whiteness(page, found ? r.prediction->whiteness_after : r.prediction->whiteness_before,
                  "innovations", "whiteness");
  } else {
    const bool found = !r.findings.empty();
    std::vector<CaseInnovations> cases;
    for (const auto& cv : r.curves) {
      const auto& sim = found ? cv.after : cv.before;
      std::vector<std::string> nodes;
      std::vector<std::vector<double>> meas, model;
      for (const auto& [node, values] : cv.measured)
        if (auto it = sim.find(node); it != sim.end()) {
          nodes.push_back(node);
          meas.push_back(values);
          model.push_back(it->second);
        }
      cases.push_back(simulated_series(cv.case_name, cv.times, nodes, meas, model));
    }
    page.paragraph(fmt::format(
        "The simulation residuals (measured − simulated) of the model {}. Output-error residuals "
        "are rarely white (they carry the slow drift of what the model still misses); their "
        "autocorrelation shows that drift's time scale and the periodogram its periods. The "
        "bounds are those of white noise, for reference. (--criterion prediction tests the "
        "innovations, which should be white.)",
        found ? "with the findings" : "as declared"));
    add_whiteness(page, test_innovations(cases), "simulation residuals", "whiteness");
  }
  if (r.structural.remains) {
    const StructuralError& e = r.structural;
    page.open_section("structural", "Structural error left");
    page.paragraph(fmt::format("RMSE {} K against a noise of about {} K, in about {} independent "
                               "points; no finding kind explains it.",
                               page_number(e.rmse, 3), page_number(r.noise_floor, 3),
                               page_number(e.independent, 3)));
    HtmlTable t;
    t.caption = "Its signature";
    t.head = {"measure", "value"};
    t.align = {Align::left, Align::right};
    for (const auto& [lag, rho] : e.autocorrelation)
      t.rows.push_back({fmt::format("autocorrelation at a lag of {} s", page_number(lag, 6)),
                        page_number(rho, 3)});
    if (e.period_s > 0.0)
      t.rows.push_back({fmt::format("share explained by a period of {} s", page_number(e.period_s)),
                        fmt::format("{:.0f} %", 100.0 * e.period_share)});
    for (const auto& in : e.inputs)
      t.rows.push_back(
          {fmt::format("correlation with {} at a lag of {} s", in.name, page_number(in.lag_s, 6)),
           page_number(in.r, 3)});
    page.table(t);
    page.close_section();
  }
  page.close_section();
}

} // namespace

std::string diagnosis_html(const DiagnosisReport& r, const lang::Model& model,
                           const std::vector<NamedInput>& inputs) {
  HtmlPage page("thermnet diagnose — " + model.name());
  add_run(page, r, inputs);
  add_summary(page, r);
  add_baseline(page, r);
  add_findings(page, r);
  if (r.prediction) add_prediction(page, r);
  add_residuals(page, r);
  page.paragraph("Written by thermnet " + std::string(THERMNET_VERSION) +
                     " (thermnet diagnose --html): one self-contained file, no script and no "
                     "external resource. Temperatures in °C on the plots, differences in K; "
                     "parameters in SI units.",
                 "note");
  return page.str();
}

} // namespace thermnet::app
