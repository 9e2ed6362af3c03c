// The diagnosis's evidence: the cases with data, the baseline simulation, the noise floor, and the
// screen's unexplained heat flows (at the declared model or on top of applied findings).

#include "kernel/diagnosis/engine.hpp"

#include "kernel/core/network.hpp"
#include "lang/elaborator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermnet::detail {

namespace {

/// Why a case's data measure no node ("" when they measure one): a boundary's temperature is
/// given, not simulated (its "error" is 0, or the difference between two inputs), so data on
/// boundaries alone give nothing to diagnose.
std::string no_node_measured(const CaseEvidence& ce) {
  std::vector<std::string> boundaries;
  if (ce.measured.series.empty()) return {};
  for (const auto& s : ce.measured.series) {
    if (!ce.spec.nodes[static_cast<std::size_t>(s.node_index)].boundary) return {};
    boundaries.push_back(s.node);
  }
  return fmt::format("case '{}': its data file {} measures no node, only the boundar{} {} (a "
                     "boundary's temperature is given, not simulated); diagnose compares "
                     "simulated nodes with measured ones: add a column of a node",
                     ce.name, ce.measured.path, boundaries.size() == 1 ? "y" : "ies",
                     fmt::join(boundaries, ", "));
}

} // namespace

void Engine::load_cases() {
  ev_.model = &model_;
  ev_.threads = opt_.threads;
  // What the findings' netlist text is written against: the declarations, and every case block.
  const lang::Reporter fail = [](lang::Diagnostic d) {
    if (d.severity == lang::Severity::error) throw lang::ModelError(std::move(d));
  };
  ev_.declared.spec = lang::Elaborator(model_, fail, nullptr, {}, false).run();
  for (const auto& name : model_.case_names())
    ev_.declared_cases.push_back({name, model_.instantiate(name)});
  place_known_events();
  std::vector<std::string> names = opt_.cases;
  const bool all = names.empty();
  if (all) names = model_.run_case_names();
  std::set<std::string> seen;
  std::string boundaries_only; // why the last case left out measures no node
  for (const auto& requested : names) {
    const std::string name = model_.resolve_case(requested);
    if (!seen.insert(name).second) continue;
    lang::NetworkSpec spec = model_.instantiate(name);
    if (spec.settings.data_path.empty()) {
      if (all) continue;
      throw DiagnosisError(fmt::format("case '{}' has no measured data (add `data \"file.csv\"` "
                                       "to the case)",
                                       name));
    }
    CaseEvidence ce;
    ce.name = name;
    ce.measured = load_measured(spec.settings.data_path, spec);
    ce.spec = std::move(spec);
    if (std::string why = no_node_measured(ce); !why.empty()) {
      if (!all) throw DiagnosisError(why);
      boundaries_only = why; // a case whose data drive boundaries only: left out, like no data
      continue;
    }
    if (ce.measured.times.size() < 10 || ce.measured.series.empty())
      throw DiagnosisError(
          fmt::format("case '{}': too few measured samples to diagnose (need at least 10)", name));
    ev_.cases.push_back(std::move(ce));
  }
  if (ev_.cases.empty() && !boundaries_only.empty()) throw DiagnosisError(boundaries_only);
  if (ev_.cases.empty())
    throw DiagnosisError("no case of the model has measured data; nothing to diagnose (add "
                         "`data \"file.csv\"` to a case)");
}

void Engine::place_known_events() {
  // A log's UNIX times are placed in each case by the first time of its data file (a model
  // without cases elaborates its default case for that: not without a log).
  if (opt_.events.empty()) return;
  std::vector<CaseClock> clocks;
  for (const auto& name : model_.run_case_names()) {
    const auto declared = std::find_if(ev_.declared_cases.begin(), ev_.declared_cases.end(),
                                       [&](const DeclaredSpec& d) { return d.case_name == name; });
    const lang::CaseSettings s = declared != ev_.declared_cases.end()
                                     ? declared->spec.settings
                                     : model_.instantiate(name).settings;
    CaseClock& c = clocks.emplace_back(CaseClock{name, s.duration.value_or(0.0), std::nullopt});
    if (s.data_layout.absolute()) c.epoch = s.data_epoch;
  }
  ev_.events = place_events(opt_.events, clocks, opt_.events_path);
}

void Engine::simulate_baseline() {
  // The declared model's series, the noise floor and the screen's evidence.
  std::vector<double> sigmas;
  for (auto& ce : ev_.cases) {
    const auto all_nodes = simulate_case(ce.spec, ce.times(), &ce.measured, &ce.simulated);
    for (std::size_t s = 0; s < ce.measured.series.size(); ++s) {
      const auto& node = ce.spec.nodes[static_cast<std::size_t>(ce.measured.series[s].node_index)];
      if (!node.boundary) sigmas.push_back(estimate_noise(ce.measured.series[s].values));
    }
    build_screen(ce, all_nodes);
    const auto& t = ce.times();
    span_.emplace_back(t.front(), t.back() - t.front());
  }
  ev_.sum_screen();
  double s2 = 0.0;
  for (double s : sigmas)
    s2 += s * s;
  ev_.noise_floor = sigmas.empty() ? 0.0 : std::sqrt(s2 / static_cast<double>(sigmas.size()));
}

namespace {

/// The times in (t0, t1] at which an input of the network jumps: the corners of its step signals
/// (boundary temperatures and element keys).
std::vector<double> jumps(const lang::NetworkSpec& spec, double t0, double t1) {
  std::vector<double> out;
  const auto add = [&](const lang::Signal& s) {
    if (s.kind() != lang::Signal::Kind::step) return;
    for (double c : s.times())
      if (c > t0 && c <= t1) out.push_back(c);
  };
  for (const auto& n : spec.nodes)
    if (n.boundary) add(n.T);
  for (const auto& e : spec.elements)
    for (const auto& [key, value] : e.values)
      add(value);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

} // namespace

void Engine::build_screen(CaseEvidence& ce, const RowMatrix& all,
                          const std::set<int>& distrusted) const {
  const auto& t = ce.times();
  const std::size_t nk = t.size(), nn = ce.spec.nodes.size();
  constexpr int half = 4;
  ce.T = all;
  ce.dTdt.assign(nk, nn, 0.0);
  ce.q.assign(nk, nn, std::numeric_limits<double>::quiet_NaN());
  ce.rows.clear();
  Network net(ce.spec);
  std::vector<int> unknown_of(nn, -1);
  for (std::size_t u = 0; u < net.unknown_nodes().size(); ++u)
    unknown_of[static_cast<std::size_t>(net.unknown_nodes()[u])] = static_cast<int>(u);
  std::vector<double> sm, sl;
  for (const auto& s : ce.measured.series) {
    const auto i = static_cast<std::size_t>(s.node_index);
    // A sensor found faulty (an applied measurement-side finding) is not trusted: its node is
    // screened with its simulated temperature, like an unmeasured one.
    if (distrusted.count(s.node_index) != 0) continue;
    smooth_series(t, s.values, half, sm, sl);
    for (std::size_t k = 0; k < nk; ++k)
      if (std::isfinite(sm[k]) && !ce.spec.nodes[i].boundary) {
        ce.T[k][i] = sm[k];
        ce.dTdt[k][i] = sl[k];
      }
    if (!ce.spec.nodes[i].boundary && ce.spec.nodes[i].C > 0.0 && unknown_of[i] >= 0)
      ce.rows.push_back(s.node_index);
  }
  // Samples whose smoothing window straddles a jump of a source or boundary are left out (the
  // corners of a step signal; a pwl signal, a measured table, is continuous and only bends).
  const std::vector<double> corners = jumps(ce.spec, t.front(), t.back());
  std::vector<double> Tu(static_cast<std::size_t>(net.size())), F(Tu.size());
  for (std::size_t k = 0; k < nk; ++k) {
    const double ta = t[k >= half ? k - half : 0], tb = t[std::min(nk - 1, k + half)];
    bool straddles = false;
    for (double c : corners)
      if (c > ta && c < tb) straddles = true;
    if (straddles) continue;
    for (std::size_t u = 0; u < net.unknown_nodes().size(); ++u)
      Tu[u] = ce.T[k][static_cast<std::size_t>(net.unknown_nodes()[u])];
    net.heat_balance(t[k], Tu.data(), F.data());
    for (int node : ce.rows) {
      const auto i = static_cast<std::size_t>(node);
      const double v =
          ce.spec.nodes[i].C * ce.dTdt[k][i] - F[static_cast<std::size_t>(unknown_of[i])];
      ce.q[k][i] = std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN();
    }
  }
}

Evidence Engine::evidence_at(const Base& base) const {
  Evidence ev = ev_;
  std::set<int> distrusted;
  for (const auto& a : base.applied)
    if (a.c.measurement_side)
      for (int i : a.c.index)
        distrusted.insert(i);
  const Stack stack(&base.applied, nullptr, nullptr);
  const Candidate none;
  for (std::size_t c = 0; c < ev.cases.size(); ++c) {
    CaseEvidence& ce = ev.cases[c];
    const lang::ParamValues ov = stack.overrides(none, {});
    ce.spec = ov.empty() ? ev_.cases[c].spec : model_.instantiate(ce.name, ov);
    stack.extend(none, {}, ce.spec);
    ce.simulated = base.sims[c];
    build_screen(ce, simulate_case(ce.spec, ce.times()), distrusted);
  }
  ev.sum_screen();
  return ev;
}

} // namespace thermnet::detail
