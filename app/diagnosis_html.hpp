#pragma once
/// The report page of `thermnet diagnose --html`: the run, the baseline, each finding with its
/// gain, significance, rivals, lines and parameters, and the residual diagnostics, as one
/// self-contained HTML file (plot/html_page.hpp).

#include "app/output_files.hpp"
#include "kernel/diagnosis/diagnosis.hpp"
#include "lang/model.hpp"

#include <string>
#include <vector>

namespace thermnet::app {

/// The page of a diagnosis of `model` (read from `inputs`).
std::string diagnosis_html(const DiagnosisReport& report, const lang::Model& model,
                           const std::vector<NamedInput>& inputs);

} // namespace thermnet::app
