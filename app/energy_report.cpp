#include "app/energy_report.hpp"

#include "app/heat_flow_report.hpp"
#include "app/report_buffer.hpp"

#include <fmt/format.h>

#include <cmath>
#include <vector>

namespace thermnet::app {

EnergyBalance energy_balance(const lang::NetworkSpec& spec, const EnergyTotals& totals) {
  EnergyBalance b;
  for (std::size_t i = 0; i < spec.nodes.size(); ++i)
    if (!spec.nodes[i].boundary)
      b.stored += spec.nodes[i].C * (totals.T_end[i] - totals.T_start[i]);
  for (std::size_t e = 0; e < spec.elements.size(); ++e) {
    const auto& el = spec.elements[e];
    for (std::size_t j = 0; j < el.nodes().size(); ++j) {
      const double q = totals.element_energy[e][j];
      if (spec.nodes[static_cast<std::size_t>(el.nodes()[j])].boundary)
        b.lost += q;
      else if (el.nodes().size() == 1)
        b.supplied += q;
    }
  }
  return b;
}

std::string energy_report(const lang::NetworkSpec& spec, const EnergyTotals& totals) {
  fmt::memory_buffer out;
  const double span = totals.t1 - totals.t0;
  put(out, "# energy balance, case {}, t = {:g} .. {:g} s (J)\n", spec.settings.name, totals.t0,
      totals.t1);
  put(out, "\n{:<20} {:>16} {:>16} {:>16} {:>12}\n", "node", "stored", "from sources",
      "through links", "residual");
  // Per node, in one pass over the elements (in their order, as a sum per node would add them):
  // the energy from its sources, through its links, and all of it (what a boundary received).
  std::vector<double> sources(spec.nodes.size()), links(spec.nodes.size()),
      received(spec.nodes.size());
  for (std::size_t e = 0; e < spec.elements.size(); ++e) {
    const auto nodes = spec.elements[e].nodes();
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      const auto i = static_cast<std::size_t>(nodes[j]);
      (nodes.size() == 1 ? sources : links)[i] += totals.element_energy[e][j];
      received[i] += totals.element_energy[e][j];
    }
  }
  for (std::size_t i = 0; i < spec.nodes.size(); ++i) {
    if (spec.nodes[i].boundary) continue;
    const double stored = spec.nodes[i].C * (totals.T_end[i] - totals.T_start[i]);
    put(out, "{:<20} {:>16.6g} {:>16.6g} {:>16.6g} {:>12.3e}\n", spec.nodes[i].name, stored,
        sources[i], links[i], stored - sources[i] - links[i]);
  }
  put(out, "\n{:<20} {:>16}\n", "boundary", "heat received");
  for (std::size_t i = 0; i < spec.nodes.size(); ++i)
    if (spec.nodes[i].boundary) put(out, "{:<20} {:>16.6g}\n", spec.nodes[i].name, received[i]);
  bool header = false;
  for (std::size_t e = 0; e < spec.elements.size(); ++e) {
    if (spec.elements[e].nodes().size() != 1) continue;
    if (!header)
      put(out, "\n{:<20} {:>16} {:>12} {:>8} {:>10}\n", "source", "energy", "on time [s]", "duty",
          "switches");
    header = true;
    const std::string switches =
        totals.switching[e] ? fmt::format("{}", totals.switches[e]) : std::string("-");
    put(out, "{:<20} {:>16.6g} {:>12.6g} {:>8.4f} {:>10}\n", element_label(spec, e),
        totals.element_energy[e][0], totals.on_time[e], span > 0 ? totals.on_time[e] / span : 0.0,
        switches);
  }
  const EnergyBalance b = energy_balance(spec, totals);
  put(out,
      "\ntotal: stored {:.6g} = supplied {:.6g} - lost to boundaries {:.6g}; residual {:.3e} J\n",
      b.stored, b.supplied, b.lost, b.residual());
  return fmt::to_string(out);
}

} // namespace thermnet::app
