// Hypothesis 'hidden_mass': a thermal mass the model lacks, tied by a conductance to an existing
// node (an object inside a box, a building's furniture and inner walls). Screen: the unexplained
// heat flow of the node regressed on lowpass_tau(T) - T, the node's own temperature through the
// mass's time constant tau = C / G (the heat the mass gives back), for a few tau; the best tau
// starts the refit of C and tau. tau is at least two sampling intervals: a mass without a lag is a
// capacity error of the node (the capacity_error kind).
#include "kernel/diagnosis/hypothesis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet {
namespace {

/// A mass's time constant at most this many times the longest case (degenerate()).
constexpr double kLongest = 3.0;

class HiddenMass final : public Hypothesis {
public:
  std::vector<Candidate> propose(const Evidence& ev) const override {
    std::vector<Candidate> out;
    if (ev.cases.empty()) return out;
    const auto& nodes = ev.cases.front().spec.nodes;
    const double min_tau = std::max(1.0, 2.0 * sampling_interval(ev));
    const std::vector<double> taus = screen_taus(ev);
    for (int a = 0; a < static_cast<int>(nodes.size()); ++a) {
      const auto& nd = nodes[static_cast<std::size_t>(a)];
      if (nd.boundary || !(nd.C > 0.0)) continue;
      Candidate c;
      c.kind = "hidden_mass";
      c.nodes = {nd.name};
      c.names = {"C", "tau"};
      c.lo = {1e-3 * nd.C, min_tau};
      // (a mass whose time constant is many times the test never fills up: see degenerate())
      c.hi = {1e3 * nd.C, std::max(2.0 * min_tau, kLongest * longest_span(ev))};
      c.index = {a};
      c.start_T = start_temperatures(ev, a);
      if (ev.unobserved(a)) { // refitted only beside a measured neighbour's hidden mass
        c.start = {nd.C, std::clamp(0.1 * longest_span(ev), min_tau, c.hi[1])};
        c.unobserved = true;
        c.evidence = fmt::format("{}; a mass tied to it shows at its measured neighbours",
                                 unscreened_words(ev, a));
        out.push_back(std::move(c));
        continue;
      }
      ScreenFit best;
      double best_tau = 0.0;
      for (double tau : taus) {
        if (tau < min_tau) continue;
        std::vector<std::vector<double>> term;
        for (const auto& ce : ev.cases) {
          std::vector<double> T(ce.T.size());
          for (std::size_t k = 0; k < T.size(); ++k)
            T[k] = ce.T[k][static_cast<std::size_t>(a)];
          std::vector<double> lag = lowpass(ce.times(), T, tau, T.empty() ? 0.0 : T.front());
          for (std::size_t k = 0; k < lag.size(); ++k)
            lag[k] -= T[k];
          term.push_back(std::move(lag));
        }
        const ScreenFit f = ev.regress(
            [&](std::size_t ci, int row, std::size_t k) { return row == a ? term[ci][k] : 0.0; },
            {a});
        if (f.coefficient > 0.0 && f.reduction > best.reduction) best = f, best_tau = tau;
      }
      if (!(best.reduction > 0.0)) continue; // no mass gives heat back to it
      c.start = {std::clamp(best.coefficient * best_tau, c.lo[0], c.hi[0]), best_tau};
      c.screen = best.reduction;
      c.evidence = fmt::format("the unexplained heat flow of {} follows its own temperature "
                               "delayed by about {:g} s (correlation {:.2f}): a mass of about "
                               "{:.3g} J/K gives heat back to it",
                               nd.name, best_tau, best.correlation, c.start[0]);
      out.push_back(std::move(c));
    }
    return out;
  }

  // A mass whose time constant reaches kLongest times the longest case hardly warms over the
  // data: it is a path to the fixed temperature it starts at (a link to a boundary, a source),
  // not a mass (on a 3 h test, a 10 h "mass" beat the radiative link to the mount boundary that
  // the truth had, S03).
  bool degenerate(const Candidate& c, const std::vector<double>& p) const override {
    return on_bound(c, p, 1, true);
  }

  std::vector<std::vector<double>> restarts(const Candidate& c) const override {
    auto out = start_restarts(c);
    for (auto& s : mass_restarts(c, 0))
      out.push_back(std::move(s));
    return out;
  }

  // A new node of capacity C, tied to the node by G = C / tau, starting at the steady state
  // around it (where the node starts as the data say; place_start).
  void extend(const Candidate& c, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    const int node = c.index[0];
    const int mass = add_tied_mass(spec, mass_name(c), p[0], std::nullopt,
                                   "a hidden mass (thermnet diagnose)", node, p[0] / p[1]);
    place_start(c, p, spec, mass, node);
  }

  // Ranged params for its capacity and conductance, so the written model is calibrated like any
  // other.
  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    return tied_mass_statements(ev, c, 0, p, mass_name(c), c.nodes[0],
                                "a mass tied to " + c.nodes[0] +
                                    " (thermnet diagnose: hidden_mass)",
                                start_text(added_starts(*this, c, p, ev)));
  }

  CaseLines case_statements(const Candidate& c, const std::vector<double>& p,
                            const Evidence& ev) const override {
    return start_case_lines(added_starts(*this, c, p, ev), unique_model_name(ev, mass_name(c)), ev);
  }

private:
  static std::string mass_name(const Candidate& c) { return "diag_hidden_" + c.nodes[0]; }
};

HypothesisPlugin make_hidden_mass() {
  return {.name = "hidden_mass",
          .doc = "a thermal mass the model lacks, tied by a conductance to a node (an object, "
                 "furniture)",
          .create = [] { return std::make_unique<HiddenMass>(); },
          .screen = "lowpass_tau(T_a) - T_a at the node, tau from 3 sampling intervals to half "
                    "the longest case",
          .fitted = "C [J/K] of the mass, tau [s] = C / G (at least two sampling intervals)",
          .writes = "ranged params diag_hidden_a_C, diag_hidden_a_G, node diag_hidden_a C = "
                    "diag_hidden_a_C T0 = (a's measured start), conductance diag_hidden_a_g "
                    "diag_hidden_a a G = diag_hidden_a_G; each case's own start in its block"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_hidden_mass);
} // namespace thermnet
