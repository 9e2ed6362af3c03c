#pragma once
/// The reports of `thermnet calibrate`: the screen table (like Table 3 of the aerial-camera study),
/// the JSON report and the measured-vs-simulated figure.

#include "kernel/calibration/optimizer.hpp"
#include "plot/svg_plot.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace thermnet::app {

/// Run facts the result itself does not carry, for the JSON report.
struct ReportContext {
  std::uint64_t seed = 1; ///< random seed
  double tolerance = 5.0; ///< acceptance limit, K
  std::string model;      ///< model file
};

/// Adds the note that R² is undefined to a result found on measured data that do not vary (its r2
/// is NaN: the table says "undefined", the JSON null).
void note_undefined_r2(OptimizerResult& r);

/// Header text of a param's column: "name [unit]" with its SI unit ("name" for bare numbers).
std::string param_heading(const lang::ParamInfo& p);

/// The table: method, samples, evaluations, accepted, RMSE [K], R², one column per param (SI,
/// with unit), wall [s]; a row of dashes for the values when no point was found.
std::string format_result_table(const OptimizerResult& r, const CalibrationProblem& problem);

/// The JSON report: {method, samples, evaluations, accepted, rmse, r2, params: {name: value},
/// wall_s} plus units ("SI"), param_units, found, cancelled, simulations, seed, tolerance_K,
/// cases, points, notes and, from least-squares methods, std_errors and correlation, and criterion
/// ("output-error"). rmse, r2 are null and params empty when nothing was found; r2 is null too when
/// it is undefined (the measured data do not vary).
nlohmann::ordered_json result_json(const OptimizerResult& r, const CalibrationProblem& problem,
                                   const ReportContext& ctx);

/// One panel per case: measured points (markers) and simulated curves at the measured times, degC.
plot::Figure comparison_figure(const std::vector<CalibrationProblem::CaseComparison>& cases,
                               const std::string& title);

} // namespace thermnet::app
