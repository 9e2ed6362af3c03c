#pragma once
/// The report page of `thermnet calibrate --html`: the run, the parameter table (start, range,
/// fitted, interval), the fit per case, the convergence of the search and the residual
/// diagnostics, as one self-contained HTML file (plot/html_page.hpp).

#include "app/calibration_report.hpp"
#include "app/output_files.hpp"
#include "app/prediction_calibration.hpp"
#include "kernel/calibration/optimizer.hpp"

#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace thermnet::app {

/// The best RMSE of a search as it went: (evaluations done, best RMSE so far in K), recorded from
/// the optimizer's progress reports (any thread).
class ConvergenceTrace {
public:
  /// Records one progress report (those before the first accepted point are skipped).
  void record(const Progress& p);
  /// The points recorded, by evaluations done.
  std::vector<std::pair<double, double>> points() const;

private:
  mutable std::mutex mutex_;
  std::vector<std::pair<double, double>> points_;
};

/// What the calibration page shows.
struct CalibrationPage {
  const lang::Model* model = nullptr;                 ///< the model calibrated
  const CalibrationProblem* problem = nullptr;        ///< its ranged params and cases
  const OptimizerResult* result = nullptr;            ///< the fit
  ReportContext context;                              ///< seed, tolerance, model path
  std::vector<NamedInput> inputs;                     ///< the files the run read
  std::vector<std::pair<double, double>> convergence; ///< ConvergenceTrace::points()
  const PredictionCalibration* prediction = nullptr;  ///< --criterion prediction: its fit
};

/// The page of a calibration.
std::string calibration_html(const CalibrationPage& page);

} // namespace thermnet::app
