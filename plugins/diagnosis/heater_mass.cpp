// Hypothesis 'heater_mass': a heater heats its node through a thermal mass of its own (a missing
// intermediate node with its capacity C and a conductance G = C / tau to the node). Screen: the
// unexplained heat flow of the heater's node regressed on lowpass_tau(P) - P, the power delayed by
// the mass's time constant tau, for a few tau; the best tau starts the refit of C and tau. tau is
// at least two sampling intervals: a shorter lag is not seen in the data, and a mass without a
// lag is a capacity error of the node (the capacity_error kind), not a heater's mass.
#include "kernel/diagnosis/hypothesis.hpp"

#include "lang/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace thermnet {
namespace {

/// Time constants the screen tries, s.
constexpr std::array<double, 6> kTaus = {60.0, 150.0, 300.0, 600.0, 1200.0, 2400.0};

/// P(t) through a first-order lag of time constant tau, at the times (from its steady state at
/// the first time when the case starts steady, else from 0: the mass starts at its node's
/// temperature).
std::vector<double> lagged(const lang::Signal& P, const std::vector<double>& times, double tau,
                           bool steady) {
  std::vector<double> out;
  out.reserve(times.size());
  double y = steady ? P.at(0.0) : 0.0, t = 0.0;
  for (double tk : times) {
    const int n = std::max(1, static_cast<int>(std::ceil((tk - t) / (tau / 20.0))));
    const double h = (tk - t) / n;
    for (int i = 0; i < n; ++i, t += h) {
      const double u = P.at(t + 0.5 * h);
      y = u + (y - u) * std::exp(-h / tau);
    }
    t = tk;
    out.push_back(y);
  }
  return out;
}

class HeaterMass final : public Hypothesis {
public:
  bool reroutes() const override { return true; }

  std::vector<Candidate> propose(const Evidence& ev) const override {
    std::vector<Candidate> out;
    if (ev.cases.empty()) return out;
    const auto& spec = ev.cases.front().spec;
    for (int e : named_heaters(spec)) {
      const auto& el = spec.elements[static_cast<std::size_t>(e)];
      const int node = el.nodes()[0];
      const double C_node = spec.nodes[static_cast<std::size_t>(node)].C;
      const bool unobserved = ev.unobserved(node);
      if (!(C_node > 0.0)) continue;
      const double min_tau = std::max(1.0, 2.0 * sampling_interval(ev));
      ScreenFit best;
      // (an unmeasured node has no unexplained heat flow to screen: the refit starts mid-range)
      double best_tau = std::max(unobserved ? kTaus[3] : kTaus.front(), min_tau);
      for (double tau : kTaus) {
        if (tau < min_tau || unobserved) continue;
        std::vector<std::vector<double>> term;
        for (const auto& ce : ev.cases) {
          const auto& P = ce.spec.elements[static_cast<std::size_t>(e)].values.at("P");
          auto lag = lagged(P, ce.times(), tau, ce.spec.settings.initial_steady);
          for (std::size_t k = 0; k < lag.size(); ++k)
            lag[k] -= P.at(ce.times()[k]);
          term.push_back(std::move(lag));
        }
        const ScreenFit f = ev.regress(
            [&](std::size_t c, int row, std::size_t k) { return row == node ? term[c][k] : 0.0; },
            {node});
        if (f.coefficient > 0.0 && f.reduction > best.reduction) {
          best = f;
          best_tau = tau;
        }
      }
      Candidate c;
      c.kind = "heater_mass";
      c.element = el.name;
      c.nodes = {spec.nodes[static_cast<std::size_t>(node)].name};
      c.names = {"C", "tau"};
      c.lo = {1e-3 * C_node, min_tau};
      c.hi = {1e2 * C_node, std::max(1e6, 10.0 * min_tau)};
      c.start = {0.5 * C_node, best_tau};
      c.screen = best.reduction;
      c.index = {e, node};
      c.unobserved = unobserved;
      c.start_T = start_temperatures(ev, node);
      c.evidence =
          unobserved
              ? fmt::format("{}; the delayed power of {} shows at its measured neighbours",
                            unscreened_words(ev, node), el.name)
              : fmt::format("the unexplained heat flow of {} follows the power of {} delayed by "
                            "about {:g} s (correlation {:.2f}): it heats through a mass",
                            c.nodes[0], el.name, best_tau, best.correlation);
      out.push_back(std::move(c));
    }
    return out;
  }

  std::vector<std::vector<double>> restarts(const Candidate& c) const override {
    auto out = start_restarts(c);
    for (auto& s : mass_restarts(c, 0))
      out.push_back(std::move(s));
    return out;
  }

  // The heater moves onto a new node of capacity C, linked to its node by G; the new node starts
  // at the steady state around it, its node's start as the data say plus the heater's power at
  // t = 0 over G (place_start).
  void extend(const Candidate& c, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    const int node = c.index[1];
    const int mass = add_tied_mass(spec, mass_name(c), p[0], std::nullopt,
                                   "the heater's own mass (thermnet diagnose)", node, p[0] / p[1]);
    spec.elements.at(static_cast<std::size_t>(c.index[0])).set_nodes(std::array{mass});
    place_start(c, p, spec, mass, node);
  }

  // A new node and its conductance; the heater's power is rerouted by two heaters (its power into
  // the mass, the same power out of its node), which read the heater's power by name (`P =
  // film.P`), so the heater's own declaration and every case's power for it stay as written.
  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    const auto& spec = ev.declared.spec;
    const auto& node = spec.nodes.at(static_cast<std::size_t>(spec.node_index(c.nodes[0])));
    const std::string m = name(ev, mass_name(c));
    const auto starts = added_starts(*this, c, p, ev);
    return fmt::format("node {} C = {} [J/K]{}\n"
                       "conductance {} {} {} G = {} [W/K]\n"
                       "heater {} {} P = {}.P\n"
                       "heater {} {} P = -{}.P",
                       m, netlist_number(p[0]),
                       starts.empty() && node.T0
                           ? " T0 = " + netlist_number(*node.T0 - lang::kZeroCelsius)
                           : start_text(starts),
                       name(ev, mass_name(c) + "_g"), m, c.nodes[0], netlist_number(p[0] / p[1]),
                       name(ev, mass_name(c) + "_in"), m, c.element,
                       name(ev, mass_name(c) + "_out"), c.nodes[0], c.element);
  }

  // The mass's start in every case block whose data start elsewhere; the power needs no line.
  CaseLines case_statements(const Candidate& c, const std::vector<double>& p,
                            const Evidence& ev) const override {
    return start_case_lines(added_starts(*this, c, p, ev), name(ev, mass_name(c)), ev);
  }

private:
  static std::string mass_name(const Candidate& c) { return "diag_mass_" + c.element; }
  static std::string name(const Evidence& ev, const std::string& base) {
    return unique_name(ev.declared.spec, base);
  }
};

HypothesisPlugin make_heater_mass() {
  return {.name = "heater_mass",
          .doc = "a heater heats its node through a thermal mass of its own (a missing node)",
          .create = [] { return std::make_unique<HeaterMass>(); },
          .screen = "lowpass_tau(P) - P at the heater's node, tau from 60 to 2400 s",
          .fitted = "C [J/K] of the mass, tau [s] = C / G (at least two sampling intervals)",
          .writes =
              "node diag_mass_h C = ..., conductance diag_mass_h_g diag_mass_h a G = C / tau, "
              "and heaters diag_mass_h_in (P = h.P, into the mass) and diag_mass_h_out (P = -h.P, "
              "out of a), which read the heater's power in every case"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_heater_mass);
} // namespace thermnet
