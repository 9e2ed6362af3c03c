#pragma once
/// The calibration problem: every ranged param of a model, every case with data.
///
/// A point x holds one value per ranged param (SI, in declaration order). Evaluating it
/// simulates every case with the params set to x, samples the simulation at the measured
/// times (dense output, so no interpolation error) and compares with the measurements.

#include "kernel/core/measured_data.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/model.hpp"

#include <atomic>
#include <optional>
#include <string>
#include <vector>

namespace thermnet {

/// How to evaluate a point.
struct EvaluationOptions {
  /// Abandon (reject) the point as soon as one |T_sim - T_meas| reaches this, K (mc/lhs).
  std::optional<double> tolerance;
  /// Keep the residual vector (least squares needs it; sampling does not).
  bool keep_residuals = false;
  /// Solver settings for every simulation.
  SolverOptions solver;
};

/// The outcome of evaluating one point.
struct Evaluation {
  bool ok = false;       ///< every case simulated (false: solver failure or invalid params)
  bool accepted = false; ///< ok and within the tolerance everywhere (always true without one)
  /// True when the point was abandoned at the first residual reaching the tolerance (ok stays
  /// true: nothing failed; sse, points, rmse and r2 then cover only the points compared so far).
  bool abandoned = false;
  std::size_t simulations = 0; ///< case simulations started (fewer than the cases if abandoned)
  double sse = 0.0;            ///< sum of squared residuals, K^2 (over the points compared)
  std::size_t points = 0;      ///< residuals compared
  double rmse = 0.0;           ///< sqrt(sse / points), K
  double r2 = 0.0; ///< 1 - sse / sum (T_meas - mean)^2, as in the study (NaN: no spread)
  std::vector<double> residuals; ///< T_sim - T_meas per point, fixed order (if kept and accepted)
  std::string failure;           ///< why it is not ok (solver message), for reports
};

/// Every ranged param and every case with data of a model; thread-safe to evaluate.
class CalibrationProblem {
public:
  /// Collects the ranged params and loads each case's data; throws lang::ModelError or
  /// lang::CsvError. `cases` restricts to these case names (empty: all cases with data); a named
  /// case without a `data` file throws std::invalid_argument. With no ranged param or no case with
  /// data the problem is empty (dimension() or cases() is 0): callers report that.
  explicit CalibrationProblem(const lang::Model& model, std::vector<std::string> cases = {});

  /// The ranged params (the dimensions of x), in declaration order.
  const std::vector<lang::ParamInfo>& params() const { return params_; }
  /// Number of dimensions.
  std::size_t dimension() const { return params_.size(); }
  /// Lower bounds (SI).
  std::vector<double> lower() const;
  /// Upper bounds (SI).
  std::vector<double> upper() const;
  /// The declared values (SI): the starting point of local methods.
  std::vector<double> initial() const;
  /// Cases that are compared, in model order.
  const std::vector<std::string>& cases() const { return cases_; }
  /// The measured data of each case (K), in the order of cases().
  const std::vector<MeasuredData>& data() const { return data_; }
  /// Total number of measured points (residuals of a full evaluation).
  std::size_t points() const;
  /// Sum over all points of (T_meas - mean T_meas)^2, K^2 (the R^2 denominator; exactly 0 when
  /// every measured point is the same).
  double total_variance() const { return sst_; }
  /// R^2 = 1 - sse / total_variance() of a sum of squared residuals; NaN (undefined) when the
  /// measured data do not vary.
  double r_squared(double sse) const;

  /// Simulates every case at x and compares with the data. Never throws for bad x: solver
  /// failures and invalid values give ok = false.
  Evaluation evaluate(const std::vector<double>& x, const EvaluationOptions& opt = {}) const;

  /// Simulated and measured series of every case at x (for plots and reports).
  struct CaseComparison {
    std::string case_name;                      ///< the case
    MeasuredData measured;                      ///< its data (K)
    std::vector<std::vector<double>> simulated; ///< per measured series, at the measured times (K)
  };
  /// Simulated vs measured at x, per case; throws on solver failure.
  std::vector<CaseComparison> compare(const std::vector<double>& x,
                                      const SolverOptions& solver = {}) const;

  /// The param values of x by name (for Model::instantiate and for reports).
  lang::ParamValues values(const std::vector<double>& x) const;

private:
  const lang::Model* model_;
  std::vector<lang::ParamInfo> params_;
  std::vector<std::string> cases_;
  std::vector<MeasuredData> data_;
  double sst_ = 0.0;
};

} // namespace thermnet
