#pragma once
/// `thermnet calibrate --criterion prediction`: the ranged params and the noise intensities at the
/// maximum of the likelihood of the one-step-ahead predictions (kernel/calibration/
/// prediction_error.hpp), reported as a calibration (the same table and JSON fields, with the
/// simulation's RMSE at the fitted params) plus the likelihood, the noise and the whiteness tests.

#include "app/calibration_report.hpp"
#include "kernel/calibration/innovation_report.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace thermnet::app {

/// What the prediction criterion found, in the forms the command writes.
struct PredictionCalibration {
  OptimizerResult result;                   ///< as a calibration: structural params, RMSE, R²
  PredictionFit fit;                        ///< every parameter and the likelihood
  std::vector<std::string> names;           ///< the names of fit.theta
  std::vector<CaseInnovations> innovations; ///< the one-step-ahead predictions at the fit
  std::vector<SeriesWhiteness> whiteness;   ///< the innovations' tests
  double one_step_rmse = 0.0;               ///< K
  nlohmann::ordered_json json;              ///< the JSON report
  std::string text;                         ///< the text report (table, likelihood, noise, tests)
};

/// The one-step-ahead predictions as CSV: case,time,node,measured,predicted,sd (degC, K).
std::string predictions_csv(const std::vector<CaseInnovations>& innovations);

/// Fits `problem`'s ranged params and the noise by maximum likelihood; `initial_sd` is the
/// initial states' standard deviation (K).
PredictionCalibration calibrate_by_prediction(const lang::Model& model,
                                              const CalibrationProblem& problem, double initial_sd,
                                              int threads, const ReportContext& ctx);

} // namespace thermnet::app
