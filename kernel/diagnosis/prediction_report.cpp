// JSON and text of a diagnosis under the prediction criterion.

#include "kernel/diagnosis/prediction_report.hpp"

#include "kernel/diagnosis/report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace thermnet {
namespace {

nlohmann::json fit_json(const LikelihoodFit& f) {
  nlohmann::json j;
  j["log_likelihood"] = f.log_likelihood;
  j["parameters"] = f.parameters;
  j["aic"] = f.aic;
  j["bic"] = f.bic;
  j["one_step_rmse"] = f.one_step_rmse;
  nlohmann::json v = nlohmann::json::object();
  for (const auto& [k, x] : f.values)
    v[k] = x;
  j["values"] = v;
  return j;
}

std::string what(const Finding& f) {
  std::string w = f.candidate.kind;
  if (!f.candidate.mechanism.empty()) w += " (" + f.candidate.mechanism + ")";
  if (!f.candidate.element.empty()) w += " " + f.candidate.element;
  return fmt::format("{} [{}]", w, fmt::join(f.candidate.nodes, ", "));
}

std::string fit_words(const LikelihoodFit& f) {
  return fmt::format("log-likelihood {:.6g} with {} parameters (AIC {:.6g}, BIC {:.6g}), "
                     "one-step-ahead RMS error {:.4g} K",
                     f.log_likelihood, f.parameters, f.aic, f.bic, f.one_step_rmse);
}

} // namespace

nlohmann::json likelihood_test_json(const LikelihoodTest& t) {
  nlohmann::json j;
  j["before"] = fit_json(t.before);
  j["after"] = fit_json(t.after);
  j["statistic"] = t.ratio.statistic;
  j["df"] = t.ratio.df;
  j["p_value"] = t.ratio.p_value;
  j["threshold"] = t.threshold;
  return j;
}

nlohmann::json prediction_json(const DiagnosisReport& r) {
  const PredictionSummary& p = *r.prediction;
  nlohmann::json j;
  j["initial_sd_K"] = p.initial_sd;
  j["alpha"] = p.alpha;
  j["declared"] = fit_json(p.declared);
  j["final"] = fit_json(p.final_fit);
  j["tested"] = p.tested;
  nlohmann::json rej = nlohmann::json::array();
  for (const auto& f : r.rejected)
    if (f.likelihood) {
      nlohmann::json x;
      x["kind"] = f.candidate.kind;
      x["nodes"] = f.candidate.nodes;
      if (!f.candidate.mechanism.empty()) x["mechanism"] = f.candidate.mechanism;
      x["values"] = finding_values(f);
      x["given"] = f.given;
      x["significant"] = f.significant;
      if (f.fit_failed) x["fit_failed"] = true;
      x["likelihood"] = likelihood_test_json(*f.likelihood);
      rej.push_back(std::move(x));
    }
  j["rejected"] = rej;
  j["whiteness_before"] = whiteness_json(p.whiteness_before);
  j["whiteness_after"] = whiteness_json(p.whiteness_after);
  j["notes"] = p.notes;
  return j;
}

std::string prediction_diagnosis_text(const DiagnosisReport& r) {
  const PredictionSummary& p = *r.prediction;
  std::string s;
  s += fmt::format("Diagnosis of {} ({} case{}: {})\n", r.model, r.cases.size(),
                   r.cases.size() == 1 ? "" : "s", fmt::join(r.cases, ", "));
  s += "Criterion: prediction error (maximum likelihood of a Kalman filter's one-step-ahead "
       "predictions, process and measurement noise fitted; findings by likelihood-ratio tests)\n";
  s += fmt::format("Declared structure, refitted: {}; simulation RMSE at the declared values "
                   "{:.3g} K\n",
                   fit_words(p.declared), r.baseline.rmse);
  s += "Whiteness of its innovations:\n" + whiteness_text(p.whiteness_before);
  if (r.findings.empty()) {
    s += fmt::format("\nNo significant finding: no candidate of the {} tested raises the "
                     "likelihood beyond chance (likelihood-ratio test at {:g}, Bonferroni-"
                     "corrected).\n",
                     p.tested, p.alpha);
  } else {
    s += "\nCauses (ranked; each given the ones above):\n";
    for (const auto& f : r.findings) {
      std::string vals;
      for (const auto& [k, v] : finding_values(f))
        vals += fmt::format("{}{} = {:.4g}", vals.empty() ? "" : ", ", k, v);
      s += fmt::format("  {}. {}: {}\n", f.rank, what(f), vals);
      s += fmt::format("     evidence: {}\n", f.evidence);
      s += fmt::format("     simulation RMSE at the fitted values {:.3g} -> {:.3g} K\n",
                       f.rmse_before, f.rmse_after);
      s += "     extension:\n";
      std::string st = f.statement;
      for (std::size_t at = 0; !st.empty() && at != std::string::npos;) {
        const std::size_t nl = st.find('\n', at);
        s +=
            "       " + st.substr(at, nl == std::string::npos ? std::string::npos : nl - at) + "\n";
        at = nl == std::string::npos ? nl : nl + 1;
        if (at >= st.size()) break;
      }
    }
    s += fmt::format("\nWith the findings: {}\n", fit_words(p.final_fit));
    s += "Whiteness of its innovations:\n" + whiteness_text(p.whiteness_after);
  }
  std::vector<const Finding*> tested;
  for (const auto& f : r.rejected)
    if (f.likelihood && !f.fit_failed) tested.push_back(&f);
  std::stable_sort(tested.begin(), tested.end(), [](const Finding* a, const Finding* b) {
    return a->likelihood->ratio.p_value < b->likelihood->ratio.p_value;
  });
  if (tested.size() > 5) tested.resize(5);
  if (!tested.empty()) s += "\nNot selected (smallest p-values first):\n";
  for (const Finding* f : tested)
    s += fmt::format("  {} (given {} finding{}): likelihood ratio {:.3g}, {} df, p = {:.3g}{}\n",
                     what(*f), f->given, f->given == 1 ? "" : "s", f->likelihood->ratio.statistic,
                     f->likelihood->ratio.df, f->likelihood->ratio.p_value,
                     f->significant ? " (significant, a better one was selected)" : "");
  std::vector<std::string> failed;
  for (const auto& f : r.rejected)
    if (f.likelihood && f.fit_failed)
      failed.push_back(
          fmt::format("{} (given {} finding{})", what(f), f.given, f.given == 1 ? "" : "s"));
  if (!failed.empty())
    s += fmt::format("\nRefits that failed (each ended below the likelihood of the model it "
                     "extends; not a measure of its gain): {}\n",
                     fmt::join(failed, "; "));
  for (const auto& n : p.notes)
    s += "note: " + n + "\n";
  return s;
}

} // namespace thermnet
