#pragma once
/// The whiteness of a fit's one-step-ahead prediction errors, series by series (a measured node of
/// a case), in the words and JSON that `calibrate` and `diagnose` share under the prediction
/// criterion.

#include "kernel/calibration/prediction_error.hpp"
#include "kernel/calibration/whiteness.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace thermnet {

/// The whiteness tests of one measured node's innovations in one case.
struct SeriesWhiteness {
  std::string case_name;     ///< the case
  std::string node;          ///< the measured node
  double innovation_rms = 0; ///< RMS of the innovations, K (the one-step-ahead error)
  Whiteness test;            ///< the tests
};

/// Tests every filtered series of every case (missing samples left out; the sampling interval is
/// the case's median time step).
std::vector<SeriesWhiteness> test_innovations(const std::vector<CaseInnovations>& cases);

/// One-step-ahead RMS error over every series, K.
double one_step_rmse(const std::vector<CaseInnovations>& cases);

/// [{case, node, n, innovation_rms, white, acf: {bound, outside, allowed, peak_lag, peak_lag_s,
/// white, values}, cpgram: {bound, max_deviation, white, frequency, cumulated}}].
nlohmann::ordered_json whiteness_json(const std::vector<SeriesWhiteness>& tests);

/// One line per series: "NODE in CASE: innovations white" or which test fails, with the numbers.
std::string whiteness_text(const std::vector<SeriesWhiteness>& tests);

} // namespace thermnet
