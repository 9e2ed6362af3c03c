#pragma once
/// What a diagnosis writes beside its report: the extended model's files, the lines of each
/// finding, the before/after figure (`thermnet diagnose --write/--plot`, the HTML page).

#include "kernel/diagnosis/diagnosis.hpp"
#include "lang/model.hpp"
#include "lang/rewrite/model_files.hpp"
#include "plot/figure.hpp"

#include <string>
#include <vector>

namespace thermnet::app {

/// The model with a finding applied, as files to write: the root (at `out`) with the new
/// statements appended under a comment that says why (capacity overrides go into every case
/// block), and rewritten copies of the included files that declare params the finding
/// recalibrated; throws rewrite::RewriteError when `out` names an input of the model.
std::vector<rewrite::RewrittenFile>
extended_model_files(const lang::Model& model, const Finding& finding, const std::string& out);
/// The root file's text of extended_model_files() (the copies of included files aside).
std::string extended_model_text(const lang::Model& model, const Finding& finding);

/// The --plot figure: measured, before and after curves of the worst nodes of every case, one
/// distinct colour per node (at most 8 nodes), titled with the model's name.
std::string diagnosis_svg(const DiagnosisReport& report, const std::string& model_name,
                          std::size_t worst = 3);

/// The figure of diagnosis_svg(): one panel per case, measured and simulated curves of the
/// `worst` nodes (by baseline RMSE): the declared model and, when `with_after`, the best finding's
/// (`Curves::after`); with `to` k >= 1, the model with findings 1..`from` (0: the declared one)
/// and the model with findings 1..k instead (`Curves::steps`).
plot::Figure diagnosis_figure(const DiagnosisReport& report, const std::string& title,
                              std::size_t worst, bool with_after, std::size_t from = 0,
                              std::size_t to = 0);

/// The comment --write puts above a finding's lines: its kind, nodes, evidence and gain.
std::string finding_comment(const Finding& finding);

/// The lines that add a finding to the model, for a person: finding_comment(), the top-level
/// statements --write appends (or the params it rewrites) and the lines of each case block.
std::string finding_lines(const Finding& finding);

} // namespace thermnet::app
