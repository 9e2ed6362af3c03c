// Hypothesis 'event_loss': a conductance between a node and a boundary that exists only while a
// known event is on (a lid or a door opened at the times of `thermnet diagnose --events`).
// Screen: the unexplained heat flow of each measured node regressed on on(t) (T_b - T_a).
#include "kernel/diagnosis/hypothesis.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace thermnet {
namespace {

class EventLoss final : public Hypothesis {
public:
  std::vector<Candidate> propose(const Evidence& ev) const override {
    std::vector<Candidate> out;
    if (ev.cases.empty() || ev.events.empty()) return out;
    const auto& nodes = ev.cases.front().spec.nodes;
    const int n = static_cast<int>(nodes.size());
    const auto names = event_names(ev.events);
    for (std::size_t e = 0; e < names.size(); ++e) {
      std::vector<lang::Signal> on;
      for (const auto& ce : ev.cases)
        on.push_back(event_schedule(ev.events, ce.name, names[e]));
      for (int a = 0; a < n; ++a) {
        // (an unmeasured node has no unexplained heat flow: its candidates are refitted only
        // beside a shortlisted one of a measured neighbour, started at its value)
        if (nodes[static_cast<std::size_t>(a)].boundary) continue;
        const bool unobserved = ev.unobserved(a);
        for (int b = 0; b < n; ++b) {
          if (!nodes[static_cast<std::size_t>(b)].boundary) continue;
          const ScreenFit f =
              unobserved
                  ? ScreenFit{.coefficient = 1.0}
                  : ev.regress(
                        [&](std::size_t c, int row, std::size_t k) {
                          if (row != a) return 0.0;
                          const auto& T = ev.cases[c].T[k];
                          return on[c].at(ev.cases[c].times()[k]) *
                                 (T[static_cast<std::size_t>(b)] - T[static_cast<std::size_t>(a)]);
                        },
                        {a});
          if (f.coefficient <= 0.0) continue; // heat would flow against the difference
          Candidate c;
          c.kind = "event_loss";
          c.nodes = {nodes[static_cast<std::size_t>(a)].name,
                     nodes[static_cast<std::size_t>(b)].name};
          c.names = {"G"};
          c.lo = {1e-6};
          c.hi = {1e4};
          c.start = {std::clamp(f.coefficient, 1e-5, 1e3)};
          c.screen = f.reduction;
          c.index = {a, b};
          c.unobserved = unobserved;
          for (const auto& w : ev.events)
            if (w.event == names[e]) c.windows.push_back(w);
          c.evidence =
              unobserved
                  ? fmt::format("{} is not measured; a loss to {} while {} is on shows at "
                                "its measured neighbours",
                                c.nodes[0], c.nodes[1], names[e])
                  : fmt::format("while {} is on, the unexplained heat flow of {} follows its "
                                "temperature difference to {} (correlation {:.2f})",
                                names[e], c.nodes[0], c.nodes[1], f.correlation);
          out.push_back(std::move(c));
        }
      }
    }
    return out;
  }

  void extend(const Candidate& c, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    lang::ElementSpec el = make_element("switched_conductance", unique_name(spec, name_of(c)),
                                        {c.index[0], c.index[1]}, {{"G", p[0]}});
    el.set("on", schedule(c, spec.settings.name));
    spec.elements.push_back(std::move(el));
  }

  // Declared with the every-case windows; a case block whose windows differ sets its own `on`.
  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    return fmt::format("switched_conductance {} {} {} G = {} [W/K] on = {}", name(ev, c),
                       c.nodes[0], c.nodes[1], netlist_number(p[0]),
                       signal_text(schedule(c, ""), ""));
  }

  CaseLines case_statements(const Candidate& c, const std::vector<double>&,
                            const Evidence& ev) const override {
    CaseLines out;
    const lang::Signal all = schedule(c, "");
    for (const auto& d : ev.declared_cases) {
      const lang::Signal own = schedule(c, d.case_name);
      if (!same_signal(own, all))
        out[d.case_name] = fmt::format("{}.on = {}", name(ev, c), signal_text(own, ""));
    }
    return out;
  }

private:
  static lang::Signal schedule(const Candidate& c, const std::string& case_name) {
    return event_schedule(c.windows, case_name, c.windows.front().event);
  }
  static std::string name_of(const Candidate& c) {
    return fmt::format("diag_{}_{}_{}", c.windows.front().event, c.nodes[0], c.nodes[1]);
  }
  static std::string name(const Evidence& ev, const Candidate& c) {
    return unique_name(ev.declared.spec, name_of(c));
  }
};

HypothesisPlugin make_event_loss() {
  return {.name = "event_loss",
          .doc = "a loss to a boundary only while a known event is on (--events: a lid opened)",
          .create = [] { return std::make_unique<EventLoss>(); },
          .screen = "on(t) (T_b - T_a), on(t) 1 during the event's windows",
          .fitted = "G [W/K] while on",
          .writes = "switched_conductance diag_EVENT_a_b a b G = ... on = step(...) (1 while "
                    "on), plus diag_EVENT_a_b.on = step(...) in each case block with its own "
                    "windows"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_event_loss);
} // namespace thermnet
