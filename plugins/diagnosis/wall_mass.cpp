// Hypothesis 'wall_mass': a thermal mass inside an existing linear link (the envelope or wall of
// a building between its air and the outdoors, a bracket between a part and its mount). The link
// a-b of conductance G is split in two around a new node m of capacity C: a-m takes the share f of
// its resistance, m-b the rest, so G_a = G / f, G_b = G / (1 - f) and the steady conductance stays
// G. Screen: the unexplained heat flow of each measured end regressed on the wall's response,
// lowpass_tau(T_eq) - T_eq with T_eq = (1 - f) T_a + f T_b (the wall's local steady state) and
// tau = C f (1 - f) / G, divided by f at a and by 1 - f at b, for a few tau and f.
#include "kernel/diagnosis/hypothesis.hpp"

#include "kernel/core/parallel.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

namespace thermnet {
namespace {

/// Shares of the link's resistance between its first end and the mass that the screen tries.
constexpr std::array<double, 5> kShares = {0.1, 0.3, 0.5, 0.7, 0.9};

/// The link's conductance in a spec, W/K (0 when it is not a linear link of constant keys).
double link_conductance(const lang::ElementSpec& e) {
  if (!e.schema || !e.schema->conductance || e.composite() != lang::Composite::none ||
      e.nodes().size() != 2)
    return 0.0;
  for (const auto& [k, v] : e.values)
    if (!v.is_constant()) return 0.0;
  const double g = e.schema->conductance(e.key_values());
  return std::isfinite(g) && g > 0.0 ? g : 0.0;
}

/// The key of a linear element its conductance is proportional (+1) or inversely proportional
/// (-1) to, or an empty name.
std::pair<std::string, int> scaling_key(const lang::ElementSpec& e) {
  const double g = e.schema->conductance(e.key_values());
  for (const auto& k : e.schema->keys) {
    auto values = e.key_values();
    auto it = values.find(k.name);
    if (it == values.end() || !(it->second > 0.0)) continue;
    it->second *= 2.0;
    const double g2 = e.schema->conductance(values);
    if (std::abs(g2 / g - 2.0) < 1e-9) return {k.name, 1};
    if (std::abs(g2 / g - 0.5) < 1e-9) return {k.name, -1};
  }
  return {"", 0};
}

class WallMass final : public Hypothesis {
public:
  bool reroutes() const override { return true; }

  std::vector<Candidate> propose(const Evidence& ev) const override {
    // Each link is screened on its own (every time constant and share, a regression over every
    // case each: seconds for a 72-node panel's links), so the links are spread over the threads,
    // each into its own slot, read in the links' order.
    if (ev.cases.empty()) return {};
    const Screen screen{sampling_interval(ev), longest_span(ev), screen_taus(ev)};
    std::vector<std::optional<Candidate>> of(ev.cases.front().spec.elements.size());
    parallel_for(of.size(), ev.threads, [&](std::size_t ei) { of[ei] = screened(ev, ei, screen); });
    std::vector<Candidate> out;
    for (auto& c : of)
      if (c) out.push_back(std::move(*c));
    return out;
  }

  // A mass at one end of the link (the share on a bound) is that node's capacity, or nothing
  // at a boundary: the capacity_error kind, not a wall.
  bool degenerate(const Candidate& c, const std::vector<double>& p) const override {
    return on_bound(c, p, 1, false) || on_bound(c, p, 1, true);
  }

  // The other places of the mass along the link (a fifth, half and four fifths of its resistance
  // on the side of the first end), each with the start's time constant C f (1 - f) / G, and the
  // start's place with a time constant four times longer and shorter.
  std::vector<std::vector<double>> restarts(const Candidate& c) const override {
    std::vector<std::vector<double>> out = start_restarts(c);
    const double f0 = c.start[1], tau_G = c.start[0] * f0 * (1.0 - f0);
    for (double f : {0.2, 0.5, 0.8})
      if (std::abs(f - f0) > 0.1) {
        std::vector<double> s = c.start;
        s[0] = std::clamp(tau_G / (f * (1.0 - f)), c.lo[0], c.hi[0]);
        s[1] = f;
        out.push_back(std::move(s));
      }
    for (double factor : {4.0, 0.25}) {
      std::vector<double> s = c.start;
      s[0] = std::clamp(s[0] * factor, c.lo[0], c.hi[0]);
      if (s[0] != c.start[0]) out.push_back(std::move(s));
    }
    return out;
  }

  // The link becomes a-m of G / f (it keeps its name) and m-b of G / (1 - f), G its conductance
  // in this case; the mass starts at the steady state between its ends, (1 - f) T_a + f T_b at
  // the first sample (place_start).
  void extend(const Candidate& c, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override {
    auto& el = spec.elements.at(static_cast<std::size_t>(c.index[0]));
    const double G = link_conductance(el);
    const int a = c.index[1], b = c.index[2];
    const int mass = add_node(spec, mass_name(c), p[0], std::nullopt,
                              "a mass inside a link (thermnet diagnose)");
    auto& link = spec.elements.at(static_cast<std::size_t>(c.index[0]));
    link = make_element("conductance", link.name, {a, mass}, {{"G", G / p[1]}});
    spec.elements.push_back(make_element("conductance", unique_name(spec, link.name + "_out"),
                                         {mass, b}, {{"G", G / (1.0 - p[1])}}));
    place_start(c, p, spec, mass, a);
  }

  // Ranged params for the capacity and the share; the link's declaration is retired and written
  // twice, a-m and m-b, with its conductance key divided by the share (or by 1 - share), so its
  // own params stay in use.
  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    const std::string m = unique_model_name(ev, mass_name(c));
    const std::string pc = unique_model_name(ev, m + "_C"), pf = unique_model_name(ev, m + "_f");
    const std::string head = fmt::format(
        "{}\n{}\nnode {} C = {}{} \"a mass inside {} (thermnet diagnose: wall_mass)\"\n",
        param_statement(pc, p[0], c.lo[0], c.hi[0], "J/K",
                        "capacity of the mass inside " + c.element),
        param_statement(pf, p[1], c.lo[1], c.hi[1], "",
                        "share of " + c.element + "'s resistance between " + c.nodes[0] +
                            " and the mass"),
        m, pc, start_text(added_starts(*this, c, p, ev)), c.element);
    const std::string in = half(ev, c, c.element, c.nodes[0], m, pf, false);
    const std::string out =
        half(ev, c, unique_model_name(ev, c.element + "_out"), m, c.nodes[1], pf, true);
    if (in.empty() || out.empty()) {
      std::string s =
          fmt::format("# wall_mass: {} is not declared by one statement of the model "
                      "file (a loop, a submodel or an included file): split it by "
                      "hand, C = {} [J/K], share {} on the side of {}",
                      c.element, netlist_number(p[0]), netlist_number(p[1]), c.nodes[0]);
      return s;
    }
    return head + in + "\n" + out;
  }

  CaseLines case_statements(const Candidate& c, const std::vector<double>& p,
                            const Evidence& ev) const override {
    if (!declaration(ev, c.element)) return {};
    return start_case_lines(added_starts(*this, c, p, ev), unique_model_name(ev, mass_name(c)), ev);
  }

  std::vector<std::string> retires(const Candidate& c, const Evidence& ev) const override {
    if (!declaration(ev, c.element)) return {};
    return {c.element};
  }

private:
  /// What every link's screen shares: the sampling interval and longest span, s, and the time
  /// constants tried.
  struct Screen {
    double dt, span;
    std::vector<double> taus;
  };

  /// The candidate of element `ei` when it is a link whose mass the data show (or cannot see).
  std::optional<Candidate> screened(const Evidence& ev, std::size_t ei,
                                    const Screen& screen) const {
    const auto& spec = ev.cases.front().spec;
    const double dt = screen.dt, span = screen.span;
    const std::vector<double>& taus = screen.taus;
    const auto& el = spec.elements[ei];
    const double G = link_conductance(el);
    if (!(G > 0.0) || el.name.empty() || overridden(ev, el.name)) return std::nullopt;
    int a = el.nodes()[0], b = el.nodes()[1];
    const auto boundary = [&](int i) { return spec.nodes[static_cast<std::size_t>(i)].boundary; };
    if (boundary(a) && boundary(b)) return std::nullopt;
    // The first end is a node, a measured one where possible.
    if (boundary(a) || (!ev.measured(a) && ev.measured(b) && !boundary(b))) std::swap(a, b);
    Candidate c;
    c.kind = "wall_mass";
    c.element = el.name;
    c.nodes = {spec.nodes[static_cast<std::size_t>(a)].name,
               spec.nodes[static_cast<std::size_t>(b)].name};
    c.names = {"C", "f"};
    c.lo = {std::max(1e-9, 0.1 * dt * G), 0.005};
    c.hi = {std::max(1.0, 1e4 * span * G), 0.995};
    c.index = {static_cast<int>(ei), a, b};
    c.start_T = start_temperatures(ev, a);
    if (!ev.measured(a) && !ev.measured(b)) {
      c.start = {std::clamp(0.1 * span * 4.0 * G, c.lo[0], c.hi[0]), 0.5};
      c.unobserved = true;
      c.evidence = fmt::format("{}; a mass inside {} shows at its measured neighbours",
                               unscreened_words(ev, a), el.name);
      return c;
    }
    ScreenFit best;
    double best_tau = 0.0, best_f = 0.5;
    for (double tau : taus)
      for (double f : kShares) {
        std::vector<std::vector<double>> term;
        for (const auto& ce : ev.cases) {
          std::vector<double> eq(ce.T.size());
          for (std::size_t k = 0; k < eq.size(); ++k)
            eq[k] = (1.0 - f) * ce.T[k][static_cast<std::size_t>(a)] +
                    f * ce.T[k][static_cast<std::size_t>(b)];
          const double y0 = ce.T.empty() ? 0.0 : ce.T.front()[static_cast<std::size_t>(a)];
          std::vector<double> y = lowpass(ce.times(), eq, tau, y0);
          for (std::size_t k = 0; k < y.size(); ++k)
            y[k] -= eq[k];
          term.push_back(std::move(y));
        }
        const ScreenFit s = ev.regress(
            [&](std::size_t ci, int row, std::size_t k) {
              if (row == a) return term[ci][k] / f;
              if (row == b) return term[ci][k] / (1.0 - f);
              return 0.0;
            },
            {a, b});
        if (s.coefficient > 0.0 && s.reduction > best.reduction)
          best = s, best_tau = tau, best_f = f;
      }
    if (!(best.reduction > 0.0)) return std::nullopt;
    c.start = {std::clamp(best_tau * G / (best_f * (1.0 - best_f)), c.lo[0], c.hi[0]), best_f};
    c.screen = best.reduction;
    c.evidence = fmt::format(
        "the unexplained heat flow of {} follows the response of a mass inside {} (time "
        "constant about {:g} s, {:.0f} % of its resistance on the side of {}; correlation "
        "{:.2f})",
        ev.measured(a) ? c.nodes[0] : c.nodes[1], el.name, best_tau, 100.0 * best_f, c.nodes[0],
        best.correlation);
    return c;
  }

  static std::string mass_name(const Candidate& c) { return "diag_wall_" + c.element; }

  /// True when a declared case changes the element's keys (its retired name would be unknown).
  static bool overridden(const Evidence& ev, const std::string& element) {
    const auto find = [&](const lang::NetworkSpec& s) -> const lang::ElementSpec* {
      for (const auto& e : s.elements)
        if (e.name == element) return &e;
      return nullptr;
    };
    const lang::ElementSpec* d = find(ev.declared.spec);
    if (!d) return true;
    for (const auto& dc : ev.declared_cases) {
      const lang::ElementSpec* e = find(dc.spec);
      if (!e || e->values.size() != d->values.size()) return true;
      for (const auto& [k, v] : d->values)
        if (!e->has(k) || !same_signal(v, e->values.at(k))) return true;
    }
    return false;
  }

  /// The declaration of an element when it is one plain statement of the model's root file.
  static const lang::ElementDecl* declaration(const Evidence& ev, const std::string& element) {
    if (!ev.model) return nullptr;
    const long root = ev.model->sources().find(ev.model->path());
    for (const auto& d : ev.model->elements())
      if (d.name == element)
        return d.element && !d.scope && root >= 0 && d.file == static_cast<lang::FileId>(root)
                   ? &d
                   : nullptr;
    return nullptr;
  }

  /// The element's statement as written, renamed `name`, between `from` and `to`, with its
  /// conductance key divided by the share (or by 1 - share); empty when it cannot be written.
  static std::string half(const Evidence& ev, const Candidate& c, const std::string& name,
                          const std::string& from, const std::string& to, const std::string& pf,
                          bool outer) {
    const lang::ElementDecl* d = declaration(ev, c.element);
    if (!d) return {};
    const lang::ElementSpec* el = nullptr;
    for (const auto& e : ev.declared.spec.elements)
      if (e.name == c.element) el = &e;
    if (!el) return {};
    const auto [key, sign] = scaling_key(*el);
    const std::string& text = ev.model->sources().text(d->file);
    const lang::ast::ElementStmt& st = *d->element;
    const std::string share = outer ? "(1 - " + pf + ")" : pf;
    struct Cut {
      std::uint32_t begin, end;
      std::string by;
    };
    std::vector<Cut> cuts{{st.name.begin, st.name.end, name}};
    // (the ends as the candidate names them, which may be the statement's swapped)
    const bool swapped =
        ev.declared.spec.nodes[static_cast<std::size_t>(el->nodes()[0])].name != c.nodes[0];
    if (st.nodes.size() != 2) return {};
    cuts.push_back({st.nodes[swapped ? 1 : 0].begin, st.nodes[swapped ? 1 : 0].end, from});
    cuts.push_back({st.nodes[swapped ? 0 : 1].begin, st.nodes[swapped ? 0 : 1].end, to});
    bool scaled = false;
    for (const auto& kv : st.keys)
      if (kv.key.name == key) {
        const auto sp = kv.value.span();
        const std::string v = text.substr(sp.begin, sp.end - sp.begin);
        cuts.push_back(
            {sp.begin, sp.end, fmt::format("({}) {} {}", v, sign > 0 ? "/" : "*", share)});
        scaled = true;
      }
    if (!scaled) return {}; // a default key carries the conductance: nothing to divide
    std::sort(cuts.begin(), cuts.end(),
              [](const Cut& x, const Cut& y) { return x.begin < y.begin; });
    std::string s;
    std::uint32_t at = st.begin;
    for (const auto& cut : cuts) {
      s += text.substr(at, cut.begin - at) + cut.by;
      at = cut.end;
    }
    s += text.substr(at, st.end - at);
    std::replace(s.begin(), s.end(), '\n', ' ');
    return s;
  }
};

HypothesisPlugin make_wall_mass() {
  return {.name = "wall_mass",
          .doc = "a thermal mass inside an existing link (an envelope or wall between a node and "
                 "a boundary or node), splitting it in two",
          .create = [] { return std::make_unique<WallMass>(); },
          .screen = "(lowpass_tau(T_eq) - T_eq) / f at a and / (1 - f) at b, T_eq = (1 - f) T_a + "
                    "f T_b, for tau and f on a grid",
          .fitted = "C [J/K] of the mass, f = share of the link's resistance between a and the "
                    "mass (the steady conductance is kept)",
          .writes = "ranged params diag_wall_e_C, diag_wall_e_f, node diag_wall_e C = "
                    "diag_wall_e_C T0 = (a's measured start); the link e is commented out and "
                    "written twice, e a diag_wall_e and e_out diag_wall_e b, its conductance key "
                    "divided by diag_wall_e_f and (1 - diag_wall_e_f)"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_wall_mass);
} // namespace thermnet
