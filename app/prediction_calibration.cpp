#include "app/prediction_calibration.hpp"

#include "lang/units.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

namespace thermnet::app {

std::string predictions_csv(const std::vector<CaseInnovations>& innovations) {
  std::string s = "case,time,node,measured,predicted,sd\n";
  auto cell = [](double v) { return std::isnan(v) ? std::string() : fmt::format("{:.10g}", v); };
  for (const auto& c : innovations)
    for (std::size_t k = 0; k < c.times.size(); ++k)
      for (std::size_t n = 0; n < c.nodes.size(); ++n)
        s += fmt::format("{},{:.10g},{},{},{},{}\n", c.case_name, c.times[k], c.nodes[n],
                         cell(c.measured[n][k] - lang::kZeroCelsius),
                         cell(c.predicted[n][k] - lang::kZeroCelsius), cell(c.sd[n][k]));
  return s;
}

PredictionCalibration calibrate_by_prediction(const lang::Model& model,
                                              const CalibrationProblem& problem, double initial_sd,
                                              int threads, const ReportContext& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  PredictionSettings settings;
  settings.initial_sd = initial_sd;
  settings.threads = threads;
  const PredictionProblem pp(model, problem, settings);
  PredictionCalibration out;
  out.fit = fit_prediction(pp);
  for (const auto& p : pp.params())
    out.names.push_back(p.name);
  const std::size_t ns = pp.structural();
  OptimizerResult& r = out.result;
  r.method = "ml";
  r.evaluations = out.fit.evaluations;
  r.found = out.fit.ok;
  r.notes = out.fit.notes;
  if (r.found) {
    r.best.assign(out.fit.theta.begin(), out.fit.theta.begin() + static_cast<long>(ns));
    EvaluationOptions eo;
    eo.solver = settings.solver;
    const Evaluation ev = problem.evaluate(r.best, eo);
    r.simulations = ev.simulations;
    r.rmse = ev.rmse;
    r.r2 = ev.r2;
    r.accepted = ev.ok ? 1 : 0;
    r.std_errors.assign(out.fit.std_errors.begin(),
                        out.fit.std_errors.begin() + static_cast<long>(ns));
    if (!out.fit.correlation.empty()) {
      r.correlation.assign(ns, std::vector<double>(ns));
      for (std::size_t i = 0; i < ns; ++i)
        for (std::size_t j = 0; j < ns; ++j)
          r.correlation[i][j] = out.fit.correlation[i][j];
    }
    out.innovations = pp.innovations(out.fit.theta);
    out.whiteness = test_innovations(out.innovations);
    out.one_step_rmse = one_step_rmse(out.innovations);
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  note_undefined_r2(r);

  using json = nlohmann::ordered_json;
  json j = result_json(r, problem, ctx);
  j["criterion"] = "prediction";
  j["log_likelihood"] = r.found ? json(out.fit.log_likelihood) : json(nullptr);
  j["parameters"] = out.fit.parameters;
  j["aic"] = r.found ? json(out.fit.aic) : json(nullptr);
  j["bic"] = r.found ? json(out.fit.bic) : json(nullptr);
  j["one_step_rmse"] = r.found ? json(out.one_step_rmse) : json(nullptr);
  j["converged"] = out.fit.converged;
  j["initial_sd_K"] = initial_sd;
  json noise = json::object(), noise_se = json::object();
  if (r.found)
    for (std::size_t k = ns; k < out.names.size(); ++k) {
      noise[out.names[k]] = out.fit.theta[k];
      noise_se[out.names[k]] =
          std::isfinite(out.fit.std_errors[k]) ? json(out.fit.std_errors[k]) : json(nullptr);
    }
  j["noise"] = noise;
  j["noise_std_errors"] = noise_se;
  j["whiteness"] = whiteness_json(out.whiteness);
  out.json = std::move(j);

  std::string& t = out.text;
  t = format_result_table(r, problem);
  t += "(param values in SI units)\n";
  t += "criterion: prediction error (maximum likelihood of the one-step-ahead predictions of a "
       "Kalman filter)\n";
  if (r.found) {
    t += fmt::format("log-likelihood {:.6g} with {} parameters over {} measurements (AIC {:.6g}, "
                     "BIC {:.6g}); one-step-ahead RMS error {:.4g} K, simulation RMSE {:.4g} K\n",
                     out.fit.log_likelihood, out.fit.parameters, out.fit.points, out.fit.aic,
                     out.fit.bic, out.one_step_rmse, r.rmse);
    t += "noise (process sigma_w in K/sqrt(s), measurement sigma_v in K):\n";
    for (std::size_t k = ns; k < out.names.size(); ++k)
      t += fmt::format("  {} = {:.4g}{}\n", out.names[k], out.fit.theta[k],
                       std::isfinite(out.fit.std_errors[k])
                           ? fmt::format(" ± {:.2g}", out.fit.std_errors[k])
                           : std::string());
    t += "whiteness of the innovations (one-step-ahead prediction errors):\n";
    t += whiteness_text(out.whiteness);
  }
  return out;
}

} // namespace thermnet::app
