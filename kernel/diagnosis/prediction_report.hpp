#pragma once
/// The prediction criterion's part of a diagnosis report: JSON and text (report.cpp calls these
/// when the report carries a PredictionSummary).

#include "kernel/diagnosis/diagnosis.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace thermnet {

/// {before: fit, after: fit, statistic, df, p_value, threshold} of a finding's test.
nlohmann::json likelihood_test_json(const LikelihoodTest& t);

/// {initial_sd_K, alpha, declared, final, tested, rejected: [...], whiteness_before,
/// whiteness_after, notes}.
nlohmann::json prediction_json(const DiagnosisReport& r);

/// The report for a person under the prediction criterion.
std::string prediction_diagnosis_text(const DiagnosisReport& r);

} // namespace thermnet
