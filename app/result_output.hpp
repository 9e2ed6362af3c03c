#pragma once
/// Simulation results as CSV (degC, the data-file format of language.md), written row by row, and
/// as an SVG plot.

#include "kernel/core/simulation.hpp"

#include <fmt/format.h>

#include <string>
#include <vector>

namespace thermnet::app {

/// The CSV header line: `time` then one column per name.
std::string result_csv_header(const std::vector<std::string>& names);

/// One CSV line: the time, then each temperature (K) in degC, or in K with `kelvin`.
std::string result_csv_row(double t, const std::vector<double>& temps, bool kelvin = false);

/// The indices of `names` that `patterns` select, in pattern order then name order, each once
/// (every index when `patterns` is empty); a pattern is a name or a glob (`*`, `?`, `[...]`).
/// Throws std::invalid_argument naming `option` and `what` for a pattern that selects nothing.
std::vector<std::size_t> select_names(const std::vector<std::string>& names,
                                      const std::vector<std::string>& patterns,
                                      const std::string& option, const std::string& what);

/// The columns of `names` that `nodes` names or globs (select_names for --nodes).
std::vector<std::size_t> plot_columns(const std::vector<std::string>& names,
                                      const std::vector<std::string>& nodes);

/// Every column of `r` against time, in degC.
std::string plot_result_svg(const SimulationResult& r, const std::string& title);

} // namespace thermnet::app
