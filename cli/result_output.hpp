#pragma once
/// Simulation results as CSV (degC, the data-file format of language.md) and as an SVG plot.

#include "kernel/core/simulation.hpp"

#include <fmt/format.h>

#include <string>
#include <vector>

namespace thermnet::cli {

/// Appends a column name as a CSV field: quoted when it holds a comma or a quote (`"p[3,7]"`).
void append_csv_field(fmt::memory_buffer& out, const std::string& name);

/// CSV text: `time` then one column per node and boundary, temperatures in degC.
std::string format_result_csv(const SimulationResult& r);

/// Node temperatures against time for the named nodes (all when empty); throws
/// std::invalid_argument for an unknown name.
std::string plot_result_svg(const SimulationResult& r, const std::vector<std::string>& nodes,
                            const std::string& title);

} // namespace thermnet::cli
