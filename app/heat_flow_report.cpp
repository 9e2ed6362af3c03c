#include "app/heat_flow_report.hpp"

#include "app/csv_writer.hpp"
#include "app/report_buffer.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <utility>
#include <vector>

namespace thermnet::app {

namespace {

using lang::kZeroCelsius;

const std::string& node_name(const lang::NetworkSpec& spec, int node) {
  return spec.nodes[static_cast<std::size_t>(node)].name;
}

/// True when the element is reported as one flow (two terminals), else per terminal.
bool two_terminal(const lang::ElementSpec& e) {
  return e.nodes().size() == 2;
}

} // namespace

std::string element_label(const lang::NetworkSpec& spec, std::size_t e) {
  const auto& el = spec.elements[e];
  return el.name.empty() ? fmt::format("#{}", e) : el.name;
}

std::vector<std::string> flow_columns(const lang::NetworkSpec& spec,
                                      const std::vector<std::size_t>& elements) {
  std::vector<std::string> columns;
  for (std::size_t e : elements) {
    const auto& el = spec.elements[e];
    if (two_terminal(el)) {
      columns.push_back(element_label(spec, e));
      continue;
    }
    for (int node : el.nodes())
      columns.push_back(fmt::format("{}@{}", element_label(spec, e), node_name(spec, node)));
  }
  return columns;
}

std::vector<double> flow_values(const lang::NetworkSpec& spec,
                                const std::vector<std::size_t>& elements,
                                const std::vector<std::vector<double>>& heat) {
  std::vector<double> values;
  for (std::size_t e : elements) {
    if (two_terminal(spec.elements[e])) {
      values.push_back(0.0 - heat[e][0]); // 0 - x: no "-0" for a zero flow
      continue;
    }
    values.insert(values.end(), heat[e].begin(), heat[e].end());
  }
  return values;
}

std::string flow_csv_header(const lang::NetworkSpec& spec,
                            const std::vector<std::size_t>& elements) {
  std::vector<std::string> fields{"time"};
  for (auto& c : flow_columns(spec, elements))
    fields.push_back(std::move(c));
  return csv_line(fields);
}

std::string flow_csv_row(double t, const lang::NetworkSpec& spec,
                         const std::vector<std::size_t>& elements,
                         const std::vector<std::vector<double>>& heat) {
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out), "{:.10g}", t);
  for (double q : flow_values(spec, elements, heat))
    fmt::format_to(std::back_inserter(out), ",{:.10g}", q);
  out.push_back('\n');
  return fmt::to_string(out);
}

std::string steady_flow_listing(const lang::NetworkSpec& spec,
                                const std::vector<std::size_t>& elements,
                                const std::vector<std::vector<double>>& heat,
                                const std::vector<double>& temps) {
  std::vector<char> listed(spec.elements.size(), 0);
  for (std::size_t e : elements)
    listed[e] = 1;
  // Each node's (element, terminal) pairs in the elements' order: one pass, not one per node.
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> at_node(spec.nodes.size());
  for (std::size_t e = 0; e < spec.elements.size(); ++e)
    for (std::size_t j = 0; j < spec.elements[e].nodes().size(); ++j)
      at_node[static_cast<std::size_t>(spec.elements[e].nodes()[j])].emplace_back(e, j);
  fmt::memory_buffer out;
  put(out, "# steady-state heat flows, case {} (W; positive: into the node)\n", spec.settings.name);
  for (std::size_t i = 0; i < spec.nodes.size(); ++i) {
    const auto& node = spec.nodes[i];
    put(out, "\n{} {}  T = {:.6f} degC\n", node.boundary ? "boundary" : "node", node.name,
        temps[i] - kZeroCelsius);
    double balance = 0.0, sources = 0.0;
    for (const auto& [e, j] : at_node[i]) {
      const auto& el = spec.elements[e];
      const double q = heat[e][j];
      balance += q;
      if (el.nodes().size() == 1) sources += q;
      if (!listed[e]) continue;
      std::string other = "(source)";
      if (two_terminal(el)) other = "from " + node_name(spec, el.nodes()[1 - j]);
      put(out, "  {:<20} {:<24} {:>16.9f}\n", element_label(spec, e), other, q);
    }
    if (sources != 0.0) put(out, "  {:<45} {:>16.9f}\n", "sources", sources);
    put(out, "  {:<45} {:>16.3e}\n",
        node.boundary ? "absorbed by the boundary" : "balance residual", balance);
  }
  return fmt::to_string(out);
}

} // namespace thermnet::app
