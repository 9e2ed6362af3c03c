#pragma once
/// Rendering a diagnosis: the JSON report of shared/spec/diagnose.md and a short text report for a
/// person.

#include "kernel/diagnosis/diagnosis.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace thermnet {

/// The JSON report (model, noise_floor, baseline, findings, plus per-case details).
nlohmann::json diagnosis_json(const DiagnosisReport& report);

/// The report for a person: worst nodes, evidence in words, ranked findings, the gain.
std::string diagnosis_text(const DiagnosisReport& report);

/// Where the time went (for --stats): wall and CPU time in all, the setup, and each refit batch.
std::string diagnosis_timing_text(const DiagnosisReport& report);

/// The fitted values of a finding by name (e.g. {"G": 0.5}).
std::map<std::string, double> finding_values(const Finding& f);

} // namespace thermnet
