// Hypothesis 'input_split': a share of a measured input (a heater's power, a solar gain given as a
// heater) heats another node, or a mass of its own, instead of the node the model gives it to.
// Two forms: into another node b (screen: the unexplained heat flows regressed on -P at the
// heater's node a and +P at b), and into a new mass tied to a (screen: a's unexplained heat flow
// regressed on lowpass_tau(P) - P, the share of the power a mass delays, for a few tau).
#include "kernel/diagnosis/hypothesis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet {
namespace {

/// The heater's power in a case, at the case's times.
std::vector<double> power_at(const CaseEvidence& ce, int e) {
  const auto& P = ce.spec.elements[static_cast<std::size_t>(e)].values.at("P");
  std::vector<double> out;
  for (double t : ce.times())
    out.push_back(P.at(t));
  return out;
}

class InputSplit final : public Hypothesis {
public:
  bool reroutes() const override { return true; }

  std::vector<Candidate> propose(const Evidence& ev) const override {
    std::vector<Candidate> out;
    if (ev.cases.empty()) return out;
    const auto& spec = ev.cases.front().spec;
    for (int e : named_heaters(spec)) {
      const auto& el = spec.elements[static_cast<std::size_t>(e)];
      const int a = el.nodes()[0];
      std::vector<std::vector<double>> P;
      for (const auto& ce : ev.cases)
        P.push_back(power_at(ce, e));
      for (int b = 0; b < static_cast<int>(spec.nodes.size()); ++b)
        if (b != a && !spec.nodes[static_cast<std::size_t>(b)].boundary &&
            spec.nodes[static_cast<std::size_t>(b)].C > 0.0)
          if (auto c = to_node(ev, el.name, e, a, b, P)) out.push_back(std::move(*c));
      if (auto c = to_mass(ev, el.name, e, a)) out.push_back(std::move(*c));
    }
    return out;
  }

  // All of the power it may move through a mass (the share on its upper bound) is the heater's
  // own mass: the heater_mass kind, with one parameter fewer.
  bool degenerate(const Candidate& c, const std::vector<double>& p) const override {
    return into_mass(c) && on_bound(c, p, 0, true);
  }

  std::vector<std::vector<double>> restarts(const Candidate& c) const override {
    if (!into_mass(c)) return {};
    auto out = start_restarts(c);
    for (auto& s : mass_restarts(c, 1))
      out.push_back(std::move(s));
    return out;
  }

  // The heater keeps (1 - share) of its power; the share heats the other node, or a new mass of
  // capacity C tied to the heater's node by G = C / tau (starting where that node starts).
  void extend(const Candidate& c, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    const auto e = static_cast<std::size_t>(c.index[0]);
    const lang::Signal P = spec.elements.at(e).values.at("P");
    const int a = c.index[1];
    int to = 0;
    if (into_mass(c)) {
      to = add_tied_mass(spec, mass_name(c), p[1], std::nullopt,
                         "a mass a share of a heater's power heats (thermnet diagnose)", a,
                         p[1] / p[2]);
    } else {
      to = c.index[2];
    }
    spec.elements[e].set("P", P.scaled(1.0 - p[0]));
    lang::ElementSpec share =
        make_element("heater", unique_name(spec, heater_name(c) + "_in"), {to}, {});
    share.set("P", P.scaled(p[0]));
    spec.elements.push_back(std::move(share));
    if (into_mass(c)) place_start(c, p, spec, to, a);
  }

  // The heater's declaration stays as written: the share is moved by two heaters (into the other
  // node or the mass, and out of the heater's node) that read its power by name (`P = 0.3 *
  // sun.P`), so they follow whatever power a case gives it, a table or an expression included.
  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    std::string s;
    std::string target = into_mass(c) ? std::string() : c.nodes[1];
    if (into_mass(c)) {
      s = tied_mass_statements(ev, c, 1, p, mass_name(c), c.nodes[0],
                               "a mass " + netlist_number(100.0 * p[0]) + " % of the power of " +
                                   c.element + " heats (thermnet diagnose: input_split)",
                               start_text(added_starts(*this, c, p, ev))) +
          "\n";
      target = unique_model_name(ev, mass_name(c));
    }
    return s + fmt::format("heater {} {} P = {} * {}.P\nheater {} {} P = {} * {}.P",
                           unique_model_name(ev, heater_name(c) + "_in"), target,
                           netlist_number(p[0]), c.element,
                           unique_model_name(ev, heater_name(c) + "_out"), c.nodes[0],
                           netlist_number(-p[0]), c.element);
  }

  // The mass's start in every case block whose data start elsewhere; the power needs no line.
  CaseLines case_statements(const Candidate& c, const std::vector<double>& p,
                            const Evidence& ev) const override {
    return into_mass(c) ? start_case_lines(added_starts(*this, c, p, ev),
                                           unique_model_name(ev, mass_name(c)), ev)
                        : CaseLines{};
  }

private:
  static bool into_mass(const Candidate& c) { return c.nodes.size() == 1; }
  static std::string heater_name(const Candidate& c) {
    return into_mass(c) ? "diag_split_" + c.element
                        : fmt::format("diag_split_{}_{}", c.element, c.nodes[1]);
  }
  static std::string mass_name(const Candidate& c) { return "diag_split_" + c.element + "_mass"; }

  /// The share of heater e (on a) that heats node b instead.
  static std::optional<Candidate> to_node(const Evidence& ev, const std::string& heater, int e,
                                          int a, int b, const std::vector<std::vector<double>>& P) {
    const auto& nodes = ev.cases.front().spec.nodes;
    Candidate c;
    c.kind = "input_split";
    c.element = heater;
    c.nodes = {nodes[static_cast<std::size_t>(a)].name, nodes[static_cast<std::size_t>(b)].name};
    c.names = {"share"};
    c.lo = {0.005};
    c.hi = {1.0};
    c.index = {e, a, b};
    if (ev.unobserved(b)) { // refitted only beside a shortlisted split into a measured neighbour
      c.start = {0.3};
      c.unobserved = true;
      c.evidence = fmt::format("{}; a share of the power of {} heating it shows at its measured "
                               "neighbours",
                               unscreened_words(ev, b), heater);
      return c;
    }
    const ScreenFit f = ev.regress(
        [&](std::size_t ci, int row, std::size_t k) {
          if (row == a) return -P[ci][k];
          if (row == b) return P[ci][k];
          return 0.0;
        },
        {a, b});
    if (!(f.coefficient > 0.0)) return std::nullopt;
    c.start = {std::clamp(f.coefficient, 0.01, 0.99)};
    c.screen = f.reduction;
    c.evidence = fmt::format("the unexplained heat flows of {} and {} follow the power of {} "
                             "with opposite signs (correlation {:.2f}): about {:.0f} % of it heats "
                             "{}",
                             c.nodes[0], c.nodes[1], heater, f.correlation, 100.0 * f.coefficient,
                             c.nodes[1]);
    return c;
  }

  /// The share of heater e (on a) that heats a mass of its own tied to a.
  static std::optional<Candidate> to_mass(const Evidence& ev, const std::string& heater, int e,
                                          int a) {
    const auto& spec = ev.cases.front().spec;
    const double C_node = spec.nodes[static_cast<std::size_t>(a)].C;
    if (!(C_node > 0.0)) return std::nullopt;
    const double min_tau = std::max(1.0, 2.0 * sampling_interval(ev));
    Candidate c;
    c.kind = "input_split";
    c.element = heater;
    c.nodes = {spec.nodes[static_cast<std::size_t>(a)].name};
    c.names = {"share", "C", "tau"};
    c.lo = {0.005, 1e-3 * C_node, min_tau};
    c.hi = {0.95, 1e3 * C_node, std::max(1e6, 100.0 * longest_span(ev))};
    c.index = {e, a};
    c.start_T = start_temperatures(ev, a);
    if (ev.unobserved(a)) {
      c.start = {0.5, C_node, std::clamp(0.1 * longest_span(ev), min_tau, c.hi[2])};
      c.unobserved = true;
      c.evidence = fmt::format("{}; a share of the power of {} delayed by a mass shows at its "
                               "measured neighbours",
                               unscreened_words(ev, a), heater);
      return c;
    }
    ScreenFit best;
    double best_tau = 0.0;
    for (double tau : screen_taus(ev)) {
      if (tau < min_tau) continue;
      std::vector<std::vector<double>> term;
      for (const auto& ce : ev.cases) {
        const std::vector<double> P = power_at(ce, e);
        std::vector<double> lag = lowpass(ce.times(), P, tau, P.empty() ? 0.0 : P.front());
        for (std::size_t k = 0; k < lag.size(); ++k)
          lag[k] -= P[k];
        term.push_back(std::move(lag));
      }
      const ScreenFit f = ev.regress(
          [&](std::size_t ci, int row, std::size_t k) { return row == a ? term[ci][k] : 0.0; },
          {a});
      if (f.coefficient > 0.0 && f.reduction > best.reduction) best = f, best_tau = tau;
    }
    if (!(best.reduction > 0.0)) return std::nullopt;
    const double share = std::clamp(best.coefficient, 0.01, 0.9);
    c.start = {share, std::clamp(0.5 * C_node, c.lo[1], c.hi[1]), best_tau};
    c.screen = best.reduction;
    c.evidence = fmt::format("the unexplained heat flow of {} follows about {:.0f} % of the power "
                             "of {} delayed by about {:g} s (correlation {:.2f}): that share heats "
                             "a mass first",
                             c.nodes[0], 100.0 * share, heater, best_tau, best.correlation);
    return c;
  }
};

HypothesisPlugin make_input_split() {
  return {.name = "input_split",
          .doc = "a share of a measured input (a heater's power, a solar gain) heats another node "
                 "or a mass of its own instead of its node",
          .create = [] { return std::make_unique<InputSplit>(); },
          .screen = "-P at the heater's node a and +P at b; or lowpass_tau(P) - P at a (into a "
                    "mass)",
          .fitted = "share (of the power); into a mass also C [J/K] and tau [s] = C / G",
          .writes = "heaters diag_split_h_b_in on b (P = share * h.P) and diag_split_h_b_out "
                    "on a (P = -share * h.P), which read the heater's power in every case; into "
                    "a mass also ranged params, node diag_split_h_mass and its conductance to a"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_input_split);
} // namespace thermnet
