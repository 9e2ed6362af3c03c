#pragma once
/// Simulation results as CSV (degC, the data-file format of language.md), written row by row, and
/// as an SVG plot.

#include "kernel/core/simulation.hpp"

#include <string>
#include <vector>

namespace thermnet::cli {

/// The CSV header line: `time` then one column per name.
std::string result_csv_header(const std::vector<std::string>& names);

/// One CSV line: the time, then each temperature (K) in degC.
std::string result_csv_row(double t, const std::vector<double>& temps);

/// The columns of `names` that `nodes` names, in that order (every column when `nodes` is empty);
/// throws std::invalid_argument for an unknown name (with a suggestion).
std::vector<std::size_t> plot_columns(const std::vector<std::string>& names,
                                      const std::vector<std::string>& nodes);

/// Every column of `r` against time, in degC.
std::string plot_result_svg(const SimulationResult& r, const std::string& title);

} // namespace thermnet::cli
