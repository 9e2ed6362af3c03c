#pragma once
/// Heat flows through the elements of a run: a CSV over time and, for a steady state, a listing per
/// node of every element's flow, like a conductor-flow report.
///
/// Sign convention: a two-terminal element's flow is the heat leaving its first node through it
/// (positive from the first node to the second); any other element gets one column per terminal,
/// NAME@NODE, the heat it puts into that node (a heater's power is positive).

#include "lang/network_spec.hpp"

#include <string>
#include <vector>

namespace thermnet::app {

/// An element's name in reports (`#INDEX` for one without a name).
std::string element_label(const lang::NetworkSpec& spec, std::size_t e);

/// The flow columns of the selected elements (spec indices): NAME, or NAME@NODE per terminal.
std::vector<std::string> flow_columns(const lang::NetworkSpec& spec,
                                      const std::vector<std::size_t>& elements);

/// The selected elements' flows, W, in flow_columns() order, from Network::element_heat.
std::vector<double> flow_values(const lang::NetworkSpec& spec,
                                const std::vector<std::size_t>& elements,
                                const std::vector<std::vector<double>>& heat);

/// The CSV header: `time` then the flow column(s) of each selected element (spec indices).
std::string flow_csv_header(const lang::NetworkSpec& spec,
                            const std::vector<std::size_t>& elements);

/// One CSV line: the time, then the selected elements' flows, W, from Network::element_heat.
std::string flow_csv_row(double t, const lang::NetworkSpec& spec,
                         const std::vector<std::size_t>& elements,
                         const std::vector<std::vector<double>>& heat);

/// The steady-state listing: per node, its temperature, the heat each selected element brings in
/// (W, negative: out), the sources' total and the balance residual (the sum over every element;
/// for a boundary, the heat it absorbs).
std::string steady_flow_listing(const lang::NetworkSpec& spec,
                                const std::vector<std::size_t>& elements,
                                const std::vector<std::vector<double>>& heat,
                                const std::vector<double>& temps);

} // namespace thermnet::app
