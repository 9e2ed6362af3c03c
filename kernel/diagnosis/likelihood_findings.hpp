#pragma once
/// What a diagnosis under the prediction criterion adds to its report: the likelihood of each
/// model it compares, the likelihood-ratio test of each finding, and the whiteness of the
/// innovations before and after (kernel/calibration/prediction_error.hpp, innovation_report.hpp).

#include "kernel/calibration/innovation_report.hpp"
#include "kernel/calibration/prediction_error.hpp"

#include <string>
#include <utility>
#include <vector>

namespace thermnet {

/// A maximum-likelihood fit of one model of the selection.
struct LikelihoodFit {
  double log_likelihood = 0.0;                        ///< at the maximum
  std::size_t parameters = 0;                         ///< fitted parameters (structural and noise)
  double aic = 0.0;                                   ///< -2 lnL + 2 k
  double bic = 0.0;                                   ///< -2 lnL + k ln n
  double one_step_rmse = 0.0;                         ///< RMS of the innovations, K
  std::vector<std::pair<std::string, double>> values; ///< every fitted parameter by name (SI)
};

/// The likelihood-ratio test of a finding against the model it extends (nested in it).
struct LikelihoodTest {
  LikelihoodFit before;   ///< the model it extends
  LikelihoodFit after;    ///< with the finding
  LikelihoodRatio ratio;  ///< 2 (lnL_after - lnL_before), added parameters, p-value
  double threshold = 0.0; ///< p-value below which it is significant (Bonferroni-corrected)
};

/// The prediction criterion's part of a diagnosis report.
struct PredictionSummary {
  double initial_sd = 1.0;                       ///< initial states' standard deviation, K
  double alpha = 0.05;                           ///< significance level of each step's tests
  LikelihoodFit declared;                        ///< the declared structure, refitted
  LikelihoodFit final_fit;                       ///< with the findings applied
  std::vector<SeriesWhiteness> whiteness_before; ///< of the declared structure's innovations
  std::vector<SeriesWhiteness> whiteness_after;  ///< of the final model's
  std::size_t tested = 0;                        ///< candidate models fitted
  std::vector<std::string> notes;                ///< remarks (kinds left out, bounds)
};

} // namespace thermnet
