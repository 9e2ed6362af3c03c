#include "kernel/diagnosis/sensor_statements.hpp"

#include <fmt/format.h>

namespace thermnet {

std::string sensor_of_node(const Evidence& ev, const std::string& node) {
  const auto& spec = ev.declared.spec;
  const int n = spec.node_index(node);
  for (const auto& e : spec.elements)
    if (e.schema && e.schema->observes && e.nodes().size() == 1 && e.nodes()[0] == n) return e.name;
  return {};
}

std::string sensor_statement(const Evidence& ev, const std::string& kind, const std::string& node,
                             const std::string& key, double value, const std::string& unit) {
  const std::string u = unit.empty() ? "" : " [" + unit + "]";
  if (const std::string own = sensor_of_node(ev, node); !own.empty())
    return fmt::format("# {}: sensor '{}' of {} reads with {} = {}{} (set in every case block)",
                       kind, own, node, key, netlist_number(value), u);
  const std::string name = unique_name(ev.declared.spec, "diag_" + kind + "_" + node);
  return fmt::format("sensor {} {} {} = {}{}", name, node, key, netlist_number(value), u);
}

CaseLines sensor_case_lines(const Evidence& ev, const std::string& node, const std::string& key,
                            double value, const std::string& unit) {
  CaseLines out;
  const std::string own = sensor_of_node(ev, node);
  if (own.empty()) return out;
  const std::string u = unit.empty() ? "" : " [" + unit + "]";
  for (const auto& d : ev.declared_cases)
    if (!d.case_name.empty())
      out[d.case_name] = fmt::format("{}.{} = {}{}", own, key, netlist_number(value), u);
  return out;
}

} // namespace thermnet
