#pragma once
/// What the report pages of diagnose and calibrate (--html) show alike: the facts of the run, the
/// whiteness of the residuals, numbers as a person reads them.

#include "app/output_files.hpp"
#include "kernel/calibration/innovation_report.hpp"
#include "plot/html_page.hpp"

#include <string>
#include <utility>
#include <vector>

namespace thermnet::app {

/// A number to `digits` significant digits; "—" when it is not finite.
std::string page_number(double v, int digits = 4);

/// The facts of the run: the model, the command, thermnet's version, the date, then `more`; and a
/// table of the files it read (role, path).
void add_run_facts(plot::HtmlPage& page, const std::string& model,
                   const std::vector<NamedInput>& inputs,
                   const std::vector<std::pair<std::string, std::string>>& more);

/// One case's simulation residuals as the whiteness tests take them: measured and simulated
/// series (K, per node, at `times`) with the simulated ones in place of the predictions.
CaseInnovations simulated_series(const std::string& case_name, const std::vector<double>& times,
                                 const std::vector<std::string>& nodes,
                                 const std::vector<std::vector<double>>& measured,
                                 const std::vector<std::vector<double>>& simulated);

/// A table of every series' whiteness tests and the figure (autocorrelation and cumulated
/// periodogram with their white-noise bounds) of the `most` series with the largest RMS error;
/// `what` names the errors tested ("innovations", "simulation residuals"), `name` the figure.
void add_whiteness(plot::HtmlPage& page, const std::vector<SeriesWhiteness>& tests,
                   const std::string& what, const std::string& name, std::size_t most = 6);

} // namespace thermnet::app
