// JSON and text rendering of a DiagnosisReport.

#include "kernel/diagnosis/report.hpp"

#include "kernel/diagnosis/prediction_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet {

namespace {

nlohmann::json node_json(const NodeMetrics& m) {
  nlohmann::json j;
  j["rmse"] = m.rmse;
  j["bias"] = m.bias;
  j["max_error"] = m.max_error;
  j["max_error_time"] = m.max_error_time;
  j["trend_mismatch_s"] = m.trend_mismatch_s;
  j["window_rmse"] = m.window_rmse;
  return j;
}

/// R² to 4 decimals, or "undefined" (NaN: the measured data do not vary).
std::string r2_text(double r2) {
  return std::isnan(r2) ? std::string("undefined") : fmt::format("{:.4f}", r2);
}

/// Nodes by falling RMSE.
std::vector<std::pair<std::string, NodeMetrics>> worst_nodes(const FitMetrics& m) {
  std::vector<std::pair<std::string, NodeMetrics>> v(m.nodes.begin(), m.nodes.end());
  std::stable_sort(v.begin(), v.end(),
                   [](const auto& a, const auto& b) { return a.second.rmse > b.second.rmse; });
  return v;
}

/// Each line of `text` after `indent`, each ending with a line break.
std::string indent_lines(const std::string& text, const std::string& indent) {
  std::string s, line;
  for (char ch : text + "\n") {
    if (ch == '\n') {
      s += indent + line + "\n";
      line.clear();
    } else {
      line += ch;
    }
  }
  return s;
}

/// One finding as JSON (the spec's fields plus the gain on all and held-out data).
nlohmann::json finding_json(const Finding& f) {
  nlohmann::json x;
  x["rank"] = f.rank;
  x["kind"] = f.candidate.kind;
  x["nodes"] = f.candidate.nodes;
  if (!f.candidate.element.empty()) x["element"] = f.candidate.element;
  if (!f.candidate.mechanism.empty()) {
    x["mechanism"] = f.candidate.mechanism;
    x["mechanism_identified"] = f.mechanism_identified;
    x["mechanism_z"] = f.mechanism_z;
    if (!f.mechanism_note.empty()) x["mechanism_note"] = f.mechanism_note;
  }
  x["values"] = finding_values(f);
  if (f.likelihood) x["likelihood"] = likelihood_test_json(*f.likelihood);
  if (!f.at_bounds.empty()) x["at_bounds"] = f.at_bounds;
  if (!f.param_rewrites.empty()) x["params"] = f.param_rewrites;
  nlohmann::json se = nlohmann::json::object();
  for (std::size_t k = 0; k < f.std_errors.size() && k < f.candidate.names.size(); ++k)
    if (std::isfinite(f.std_errors[k])) se[f.candidate.names[k]] = f.std_errors[k];
  x["std_errors"] = se;
  if (!f.start.empty()) x["start"] = f.start;
  x["statement"] = f.statement;
  if (!f.retired.empty()) x["retired"] = f.retired;
  x["case_statements"] = f.case_statements;
  x["evidence"] = f.evidence;
  x["rmse_before"] = f.rmse_before;
  x["rmse_after"] = f.rmse_after;
  x["r2_before"] = f.r2_before;
  x["r2_after"] = f.r2_after;
  x["validation_rmse_before"] = f.validation_rmse_before;
  x["validation_rmse_after"] = f.validation_rmse_after;
  x["validation_r2_before"] = f.validation_r2_before;
  x["validation_r2_after"] = f.validation_r2_after;
  x["delta_bic"] = f.delta_bic;
  x["holdout_z"] = f.holdout_z;
  if (std::isfinite(f.block_gain)) x["block_gain"] = f.block_gain;
  if (std::isfinite(f.window_gain)) x["window_gain"] = f.window_gain;
  if (f.given > 0) x["given"] = f.given;
  if (!f.rivals.empty()) {
    // The ambiguity set: the finding itself first, then the candidates that fit as well.
    nlohmann::json cands = nlohmann::json::array();
    auto member = [](const Candidate& c, const std::vector<double>& values, double rmse,
                     double held, double z) {
      nlohmann::json m;
      m["kind"] = c.kind;
      m["nodes"] = c.nodes;
      if (!c.element.empty()) m["element"] = c.element;
      if (!c.mechanism.empty()) m["mechanism"] = c.mechanism;
      nlohmann::json v = nlohmann::json::object();
      for (std::size_t k = 0; k < values.size() && k < c.names.size(); ++k)
        v[c.names[k]] = values[k];
      m["values"] = v;
      m["rmse"] = rmse;
      m["validation_rmse"] = held;
      m["z"] = z;
      return m;
    };
    cands.push_back(member(f.candidate, f.values, f.rmse_after, f.validation_rmse_after, 0.0));
    for (const auto& r : f.rivals)
      cands.push_back(member(r.candidate, r.values, r.rmse_after, r.validation_rmse_after, r.z));
    x["candidates"] = cands;
    x["separate_by"] = f.separate_by;
  }
  return x;
}

} // namespace

std::map<std::string, double> finding_values(const Finding& f) {
  std::map<std::string, double> v;
  for (std::size_t j = 0; j < f.values.size() && j < f.candidate.names.size(); ++j)
    v[f.candidate.names[j]] = f.values[j];
  return v;
}

nlohmann::json diagnosis_json(const DiagnosisReport& r) {
  nlohmann::json j;
  j["model"] = r.model;
  j["cases"] = r.cases;
  j["noise_floor"] = r.noise_floor;
  j["at_noise_floor"] = r.at_noise_floor;
  j["min_gain"] = r.min_gain;
  nlohmann::json base;
  base["rmse"] = r.baseline.rmse;
  base["r2"] = r.baseline.r2;
  base["nodes"] = nlohmann::json::object();
  for (const auto& [name, m] : r.baseline.nodes)
    base["nodes"][name] = node_json(m);
  base["cases"] = nlohmann::json::object();
  for (const auto& [cname, nodes] : r.baseline.cases) {
    nlohmann::json c = nlohmann::json::object();
    for (const auto& [name, m] : nodes)
      c[name] = node_json(m);
    base["cases"][cname] = {{"nodes", c}};
  }
  j["baseline"] = base;
  j["findings"] = nlohmann::json::array();
  for (const auto& f : r.findings)
    j["findings"].push_back(finding_json(f));
  j["alternatives"] = nlohmann::json::array();
  for (const auto& f : r.alternatives)
    j["alternatives"].push_back(finding_json(f));
  if (r.structural.remains) {
    const StructuralError& e = r.structural;
    nlohmann::json x;
    x["rmse"] = e.rmse;
    x["independent_points"] = e.independent;
    x["autocorrelation"] = nlohmann::json::array();
    for (const auto& [lag, rho] : e.autocorrelation)
      x["autocorrelation"].push_back({{"lag_s", lag}, {"r", rho}});
    x["period_s"] = e.period_s;
    x["period_share"] = e.period_share;
    x["inputs"] = nlohmann::json::array();
    for (const auto& in : e.inputs)
      x["inputs"].push_back({{"input", in.name}, {"lag_s", in.lag_s}, {"r", in.r}});
    j["structural_error"] = x;
  }
  // The refitted candidates that were not significant, briefly (what the rule turned down).
  j["rejected"] = nlohmann::json::array();
  for (const auto& f : r.rejected) {
    nlohmann::json x = {{"kind", f.candidate.kind},
                        {"nodes", f.candidate.nodes},
                        {"values", finding_values(f)},
                        {"rmse_after", f.rmse_after},
                        {"validation_rmse_after", f.validation_rmse_after},
                        {"holdout_z", f.holdout_z},
                        {"delta_bic", f.delta_bic}};
    if (!f.candidate.element.empty()) x["element"] = f.candidate.element;
    if (!f.candidate.mechanism.empty()) x["mechanism"] = f.candidate.mechanism;
    if (std::isfinite(f.window_gain)) x["window_gain"] = f.window_gain;
    if (f.given > 0) x["given"] = f.given;
    if (f.fit_failed) x["fit_failed"] = true;
    j["rejected"].push_back(std::move(x));
  }
  j["validation"] = {{"method", r.validation}, {"folds", r.folds}};
  j["criterion"] = r.criterion;
  if (r.prediction) j["prediction"] = prediction_json(r);
  if (!r.split_cases.empty()) j["validation"]["split_cases"] = r.split_cases;
  if (!r.case_folds.empty()) j["validation"]["case_folds"] = r.case_folds;
  j["screened"] = r.screened;
  j["refitted"] = r.refitted;
  j["wall_s"] = r.wall_s;
  return j;
}

std::string diagnosis_timing_text(const DiagnosisReport& r) {
  std::string s = fmt::format("thermnet diagnose: {:.1f} s wall, {:.1f} s CPU; setup (data, "
                              "baseline, heat flows) {:.2f} s wall; {} screened, {} refitted\n",
                              r.wall_s, r.cpu_s, r.setup_wall_s, r.screened, r.refitted);
  for (std::size_t i = 0; i < r.batches.size(); ++i) {
    const RefitBatch& b = r.batches[i];
    if (b.likelihoods > 0) {
      s += fmt::format("  likelihood step {}: {} candidate{} on {} finding{}: {} likelihoods, "
                       "{:.1f} s wall, {:.1f} s CPU\n",
                       b.base_findings + 1, b.refits, b.refits == 1 ? "" : "s", b.base_findings,
                       b.base_findings == 1 ? "" : "s", b.likelihoods, b.wall_s, b.cpu_s);
      continue;
    }
    const std::string sens =
        b.sensitivity_runs ? fmt::format(" ({} with sensitivities)", b.sensitivity_runs) : "";
    s += fmt::format("  refits {}: {} {}on {} finding{}: {} simulations{}, {:.1f} s wall, {:.1f} s "
                     "CPU\n",
                     i + 1, b.refits, b.joint ? "jointly with the ranged params " : "",
                     b.base_findings, b.base_findings == 1 ? "" : "s", b.simulations, sens,
                     b.wall_s, b.cpu_s);
  }
  return s;
}

namespace {

/// A duration in the unit that reads best (s, min, h or d).
std::string duration_words(double s) {
  if (s >= 2 * 86400.0) return fmt::format("{:.3g} d", s / 86400.0);
  if (s >= 2 * 3600.0) return fmt::format("{:.3g} h", s / 3600.0);
  if (s >= 120.0) return fmt::format("{:.3g} min", s / 60.0);
  return fmt::format("{:.3g} s", s);
}

/// "Structural error remains" with its signature.
std::string structural_text(const DiagnosisReport& r) {
  const StructuralError& e = r.structural;
  std::string s = fmt::format(
      "\nStructural error remains: RMSE {:.3g} K {}against a measurement noise of about {:.3g} K, "
      "in about {:.0f} independent points; no finding kind explains it. Its signature:\n",
      e.rmse, r.findings.empty() ? "" : "after the findings ", r.noise_floor, e.independent);
  std::vector<std::string> acf;
  for (const auto& [lag, rho] : e.autocorrelation)
    acf.push_back(fmt::format("{:.2f} at {}", rho, duration_words(lag)));
  if (!acf.empty()) s += fmt::format("  autocorrelation: {}\n", fmt::join(acf, ", "));
  if (e.period_s > 0.0)
    s += fmt::format("  periodogram: a period of {} explains {:.0f} % of it{}\n",
                     duration_words(e.period_s), 100.0 * e.period_share,
                     std::abs(e.period_s / 86400.0 - 1.0) < 0.1
                         ? " (a daily period: a daily input is missing or mis-modelled)"
                         : "");
  for (std::size_t i = 0; i < e.inputs.size() && i < 4; ++i)
    s += fmt::format("  follows {} with correlation {:+.2f} at a lag of {}\n", e.inputs[i].name,
                     e.inputs[i].r, duration_words(e.inputs[i].lag_s));
  return s;
}

} // namespace

std::string diagnosis_text(const DiagnosisReport& r) {
  if (r.prediction) return prediction_diagnosis_text(r);
  std::string s;
  s += fmt::format("Diagnosis of {} ({} case{}: {})\n", r.model, r.cases.size(),
                   r.cases.size() == 1 ? "" : "s", fmt::join(r.cases, ", "));
  s += fmt::format("Baseline: RMSE {:.3g} K, R² {}; measurement noise about {:.3g} K\n",
                   r.baseline.rmse,
                   std::isnan(r.baseline.r2)
                       ? "undefined (every measured point has the same value: no spread to explain)"
                       : r2_text(r.baseline.r2),
                   r.noise_floor);
  s += "\nWhat the simulation gets wrong (worst nodes):\n";
  auto worst = worst_nodes(r.baseline);
  // A series the simulation matches exactly (a boundary read from the data it is given) is not
  // something the simulation gets wrong.
  std::erase_if(worst, [](const auto& w) { return w.second.points == 0 || w.second.rmse == 0.0; });
  if (worst.empty()) s += "  nothing: every measured series is matched exactly\n";
  for (std::size_t i = 0; i < worst.size() && i < 3; ++i) {
    const auto& [name, m] = worst[i];
    s += fmt::format("  {:<14} RMSE {:.3g} K, bias {:+.3g} K, largest error {:+.3g} K at t = "
                     "{:.0f} s (case {})",
                     name, m.rmse, m.bias, m.max_error, m.max_error_time, m.max_error_case);
    if (m.longest_mismatch_s > 0)
      s += fmt::format("; measured {} for {:.0f} s from t = {:.0f} s while simulated {}",
                       m.measured_rising ? "rises" : "falls", m.longest_mismatch_s,
                       m.longest_mismatch_start, m.measured_rising ? "falls" : "rises");
    s += "\n";
  }
  if (r.findings.empty()) {
    s += r.at_noise_floor
             ? "\nNo finding: the remaining error is at the measurement noise floor.\n"
             : fmt::format("\nNo significant finding: no candidate extension predicts held-out "
                           "data better beyond chance and lowers the error by at least {:.3g} K "
                           "somewhere (--min-gain).\n",
                           r.min_gain);
    if (r.structural.remains) s += structural_text(r);
    return s;
  }
  std::string validation;
  // (with several cases to a fold: the other folds)
  const std::string others =
      r.case_folds.empty()
          ? std::string("the others")
          : fmt::format("the other {} of {} folds of the {} cases", r.case_folds.size() - 1,
                        r.case_folds.size(), r.cases.size() - r.split_cases.size());
  if (r.validation == "leave_one_case_out")
    validation = fmt::format("each case predicted by a fit to the other {}", r.folds - 1);
  else if (r.validation == "case_folds")
    validation = fmt::format("each case predicted by a fit to {}", others);
  else if (r.validation == "held_back_time")
    validation = fmt::format("each of {} equal stretches of the case predicted by a fit to the "
                             "others",
                             r.folds);
  else
    validation = fmt::format("each case predicted by a fit to {}, and each equal stretch "
                             "of {} (an event no other case has) by a fit to the rest",
                             others, fmt::join(r.split_cases, ", "));
  s += "\nCauses (ranked; each given the ones above):\n";
  for (const auto& f : r.findings) {
    std::string what = f.candidate.kind;
    if (!f.candidate.mechanism.empty()) what += " (" + f.candidate.mechanism + ")";
    if (!f.candidate.element.empty()) what += " " + f.candidate.element;
    std::string vals;
    for (const auto& [k, v] : finding_values(f)) {
      vals += fmt::format("{}{} = {:.4g}", vals.empty() ? "" : ", ", k, v);
      if (auto b = f.at_bounds.find(k); b != f.at_bounds.end())
        vals += fmt::format(" (on its {} bound)", b->second);
    }
    s += fmt::format("  {}. {} [{}]: {}\n", f.rank, what, fmt::join(f.candidate.nodes, ", "), vals);
    s += fmt::format("     evidence: {}\n", f.evidence);
    if (!f.at_bounds.empty()) {
      std::vector<std::string> names;
      for (const auto& [k, side] : f.at_bounds)
        names.push_back(k);
      s += fmt::format("     note: {} ended on a bound of the fitted range: the data push it "
                       "beyond, so it is a limit, not an estimate\n",
                       fmt::join(names, ", "));
    }
    if (!f.mechanism_note.empty()) s += fmt::format("     mechanism: {}\n", f.mechanism_note);
    if (f.given > 0)
      s += fmt::format("     given finding{} {} applied\n", f.given > 1 ? "s" : "",
                       f.given > 1 ? fmt::format("1-{}", f.given) : std::string("1"));
    s += fmt::format("     gain: RMSE {:.3g} -> {:.3g} K, R² {} -> {}; held-out RMSE "
                     "{:.3g} -> {:.3g} K ({})\n",
                     f.rmse_before, f.rmse_after, r2_text(f.r2_before), r2_text(f.r2_after),
                     f.validation_rmse_before, f.validation_rmse_after, validation);
    if (!f.rivals.empty()) {
      s += "     fits as well (held-out test cannot tell them apart):\n";
      for (const auto& r : f.rivals)
        s += fmt::format(
            "       {}{} [{}]: RMSE {:.3g} K, held-out {:.3g} K (z = {:.2g})\n", r.candidate.kind,
            r.candidate.mechanism.empty() ? "" : " (" + r.candidate.mechanism + ")",
            fmt::join(r.candidate.nodes, ", "), r.rmse_after, r.validation_rmse_after, r.z);
      s += fmt::format("     to separate them: {}\n", f.separate_by);
    }
    if (!f.start.empty()) s += fmt::format("     start: {}\n", f.start);
    s += "     extension:\n";
    if (!f.retired.empty())
      s += fmt::format("       (replacing {}: --write comments out its declaration)\n",
                       fmt::join(f.retired, ", "));
    if (!f.statement.empty()) s += indent_lines(f.statement, "       ");
    for (const auto& [name, lines] : f.case_statements)
      s += fmt::format("       in case {}:\n", name) + indent_lines(lines, "         ");
  }
  if (r.structural.remains) s += structural_text(r);
  std::vector<std::string> failed;
  for (const auto& f : r.rejected)
    if (f.fit_failed)
      failed.push_back(fmt::format("{}{} [{}]", f.candidate.kind,
                                   f.candidate.element.empty() ? "" : " " + f.candidate.element,
                                   fmt::join(f.candidate.nodes, ", ")));
  if (!failed.empty())
    s += fmt::format("\nRefits that failed (no step from any of their starts lowered the error; "
                     "not a measure of their gain): {}\n",
                     fmt::join(failed, "; "));
  if (!r.alternatives.empty()) {
    s += "\nAlso significant alone, explained by the findings above:\n";
    for (const auto& f : r.alternatives)
      s += fmt::format("  {}{} [{}]: RMSE {:.3g} K, held-out {:.3g} K\n", f.candidate.kind,
                       f.candidate.mechanism.empty() ? "" : " (" + f.candidate.mechanism + ")",
                       fmt::join(f.candidate.nodes, ", "), f.rmse_after, f.validation_rmse_after);
  }
  return s;
}

} // namespace thermnet
