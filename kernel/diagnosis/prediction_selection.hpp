#pragma once
/// The diagnosis under the prediction criterion (internal to kernel/diagnosis): every structure is
/// refitted by maximum likelihood of its one-step-ahead predictions (ranged params, the
/// candidate's own parameters and the noise intensities; kernel/calibration/prediction_error.hpp),
/// and a candidate is a finding when the likelihood-ratio test against the model it extends
/// rejects that model (chi-square with the added parameter count, Bonferroni-corrected over the
/// candidates of the step). Forward selection: the best significant candidate (lowest BIC) is
/// applied and the next step tests the others on top of it. The candidates are the hypothesis
/// plugins' model-side ones, shortlisted by their screen score.

#include "kernel/diagnosis/engine.hpp"

namespace thermnet::detail {

/// Fills the report's findings, rejected candidates and prediction summary; returns the base with
/// the findings applied (at their fitted values; the ranged params as declared) for the curves.
Base select_by_likelihood(const Engine& engine, const DiagnosisOptions& options,
                          DiagnosisReport& rep);

} // namespace thermnet::detail
