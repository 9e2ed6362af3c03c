// The diagnosis's least-squares Jacobians from forward sensitivities (the cases' CVODES
// sensitivities carried through the measurement-side corrections) against central differences of
// simulations: every hypothesis kind, refitted on the declared model, jointly with the ranged
// params, on top of an applied finding and composed with one; networks that cannot integrate
// sensitivities give none (the least-squares core then differences simulations).

#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "kernel/diagnosis/composites.hpp"
#include "kernel/diagnosis/engine.hpp"
#include "kernel/diagnosis/events.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

namespace {

using namespace thermnet;
using namespace thermnet::detail;

/// Four nodes in air (c's neighbour u unmeasured), two heaters, two cases with data and a lid
/// opening in each; {EXTRA} takes the truth's hidden link.
const char* kModel = R"(model hyp
param h_air = 8 [W/(m^2*K)] range 4 .. 16
param k = 0.5 [W/K] range 0.2 .. 1
boundary air T = pwl(0: 20, 3000: 24)
node a C = 500 [J/K] T0 = 20
node b C = 800 [J/K] T0 = 21
node c C = 300 [J/K] T0 = 20
node u C = 400 [J/K] T0 = 19
conductance gab a b G = k
conductance gbc b c G = 0.3
conductance gcu c u G = 0.2
convection ca a air h = h_air A = 0.02
convection cb b air h = h_air A = 0.03
convection cc c air h = h_air A = 0.02
convection cu u air h = h_air A = 0.01
heater q a P = 0
heater r c P = 0
{EXTRA}
case one { duration = 7200; output = 60; q.P = step(0: 5, 3000: 1); r.P = 2{DATA:one} }
case two { duration = 7200; output = 60; q.P = 2; r.P = step(0: 0, 1800: 4){DATA:two} }
)";

std::string fill(std::string text, const std::string& extra, bool data) {
  const auto replace = [&](const std::string& key, const std::string& by) {
    for (auto p = text.find(key); p != std::string::npos; p = text.find(key))
      text.replace(p, key.size(), by);
  };
  replace("{EXTRA}", extra);
  for (const char* c : {"one", "two"})
    replace(fmt::format("{{DATA:{}}}", c), data ? fmt::format("; data \"{}.csv\"", c) : "");
  return text;
}

/// The data of nodes a, b, c: the model with a hidden link between a and c (no noise needed for a
/// derivative), in degC.
void write_data(const test::TempDir& dir) {
  test::LoadedModel truth(
      dir.write("truth.tnet", fill(kModel, "conductance hid a c G = 0.25", false)),
      test::Lint::clean);
  for (const char* c : {"one", "two"}) {
    Network net(truth.model->instantiate(c));
    const SimulationResult r = simulate(net);
    std::string csv = "time,a,b,c\n";
    for (std::size_t k = 0; k < r.times.size(); ++k) {
      csv += fmt::format("{}", r.times[k]);
      for (const char* n : {"a", "b", "c"})
        csv += fmt::format(",{:.4f}",
                           r.temps[k][static_cast<std::size_t>(net.spec().node_index(n))] - 273.15);
      csv += "\n";
    }
    dir.write(fmt::format("{}.csv", c), csv);
  }
}

/// Largest |J_sens - J_diff| of a column over its largest |J_sens|, worst column.
double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  double worst = 0.0;
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    const double size = a.col(j).cwiseAbs().maxCoeff();
    worst = std::max(worst, (a.col(j) - b.col(j)).cwiseAbs().maxCoeff() / std::max(size, 1e-300));
  }
  return worst;
}

/// The two Jacobians of an entry at its start agree (and are not zero).
void check_entry(const Engine& engine, const Entry& e, const Base& base, const std::string& what) {
  INFO(what);
  const Eigen::MatrixXd sens = engine.residual_jacobian(e, base, e.c.start, false);
  const Eigen::MatrixXd diff = engine.residual_jacobian(e, base, e.c.start, true);
  REQUIRE(sens.size() > 0);
  REQUIRE(diff.rows() == sens.rows());
  REQUIRE(diff.cols() == sens.cols());
  for (Eigen::Index j = 0; j < sens.cols(); ++j) {
    INFO("parameter ", j, " (",
         e.c.names.size() > static_cast<std::size_t>(j) ? e.c.names[static_cast<std::size_t>(j)]
                                                        : "ranged",
         ")");
    CHECK(sens.col(j).cwiseAbs().maxCoeff() > 1e-9);
  }
  // Both carry the integration's error at the diagnosis's rtol of 1e-7 (steps of 1e-3 of each
  // parameter for the differences), each its own: measured up to 1.8 % of a column (hidden_mass's
  // tau; 0.16 % with both at rtol 1e-10), 1e-4 for most; a wrong derivative is off by its size.
  CHECK(relative_difference(sens, diff) < 0.03);
}

TEST_CASE("diagnosis Jacobian: sensitivities agree with central differences for every kind") {
  test::TempDir dir;
  write_data(dir);
  test::LoadedModel m(dir.write("model.tnet", fill(kModel, "", true)), test::Lint::clean);
  DiagnosisOptions opt;
  opt.threads = 1;
  opt.events = parse_events("case,event,start,end\none,lid,1200,2400\ntwo,lid,3600,4800\n",
                            "ev.csv", {"one", "two"});
  const Engine engine(*m.model, opt);
  std::vector<std::unique_ptr<Hypothesis>> owned;
  std::set<std::string> kinds;
  const Hypothesis* param_h = nullptr;
  Candidate param_c;
  std::vector<Entry> entries;
  for (const auto& name : HypothesisRegistry::global().names()) {
    owned.push_back(HypothesisRegistry::global().find(name)->create());
    const Hypothesis* h = owned.back().get();
    std::set<std::string> mechanisms;
    for (const Candidate& c : h->propose(engine.evidence())) {
      if (c.start.empty() || mechanisms.count(c.mechanism)) continue;
      mechanisms.insert(c.mechanism);
      entries.push_back(Entry{h, c, h, c, {}});
      if (h->recalibrates()) param_h = h, param_c = c;
    }
    kinds.insert(name);
  }
  // every kind proposes here (the events give event_loss its windows)
  std::set<std::string> proposed;
  for (const auto& e : entries)
    proposed.insert(e.c.kind);
  CHECK(proposed == kinds);
  for (const auto& e : entries)
    check_entry(engine, e, engine.declared(),
                fmt::format("{} {} [{}]", e.c.kind, e.c.mechanism, fmt::join(e.c.nodes, ", ")));

  REQUIRE(param_h != nullptr);
  SUBCASE("jointly with the ranged params, on top of an applied finding") {
    std::vector<std::unique_ptr<Joint>> joints;
    for (const auto& e : entries) {
      if (e.h->recalibrates()) continue;
      joints.push_back(std::make_unique<Joint>(e.h, e.c, param_h, param_c));
      const Candidate jc = joints.back()->candidate(param_c.start);
      check_entry(engine, Entry{joints.back().get(), jc, e.h, e.c, {}}, engine.declared(),
                  fmt::format("joint {} {}", e.c.kind, e.c.mechanism));
    }
    // a sensor offset applied; a link and a lag on top of it
    const auto find = [&](const std::string& kind) {
      for (const auto& e : entries)
        if (e.c.kind == kind) return e;
      FAIL("no candidate of ", kind);
      return entries.front();
    };
    const Entry offset = find("sensor_offset");
    const Base base = engine.make_base({Applied{offset.h, offset.c, {0.4}}});
    for (const char* kind : {"missing_link", "sensor_lag", "capacity_error"})
      check_entry(engine, find(kind), base, fmt::format("{} on an applied offset", kind));
    // findings re-estimated together: a link (model side) and an offset (measurement side) as one
    // composite, whose offset only its correction moves
    const Entry link = find("missing_link");
    const Compose both({Applied{link.h, link.c, link.c.start}, Applied{offset.h, offset.c, {0.4}}});
    check_entry(engine, Entry{&both, both.candidate(), link.h, link.c, {}}, engine.declared(),
                "a link and an offset composed");
  }
}

TEST_CASE("diagnosis Jacobian: no sensitivities through a thermostat or a sensor element") {
  test::TempDir dir;
  write_data(dir);
  const std::unique_ptr<Hypothesis> link =
      HypothesisRegistry::global().find("missing_link")->create();
  const auto first_candidate = [&](const Engine& engine) {
    for (const Candidate& c : link->propose(engine.evidence()))
      if (!c.start.empty()) return Entry{link.get(), c, link.get(), c, {}};
    FAIL("no missing_link candidate");
    return Entry{};
  };
  DiagnosisOptions opt;
  opt.threads = 1;
  for (const char* extra : {"thermostat t b P = 1 on = 15 off = 17", "sensor sa a offset = 0.1"}) {
    INFO(extra);
    test::LoadedModel m(dir.write("model.tnet", fill(kModel, extra, true)), test::Lint::clean);
    const Engine engine(*m.model, opt);
    const Entry e = first_candidate(engine);
    CHECK(engine.residual_jacobian(e, engine.declared(), e.c.start, false).size() == 0);
    // the differences still work there (what the least-squares core falls back to)
    const Eigen::MatrixXd diff = engine.residual_jacobian(e, engine.declared(), e.c.start, true);
    REQUIRE(diff.cols() == static_cast<long>(e.c.start.size()));
    CHECK(diff.cwiseAbs().maxCoeff() > 1e-9);
  }
}

} // namespace

TEST_CASE("diagnosis Jacobian: heaters driven by a table of measured inputs") {
  // The measured house's heaters read a CSV column (table()): their kinds' derivatives must follow
  // the power over time, not its start.
  test::TempDir dir;
  write_data(dir);
  std::string inputs = "time,Qa,Qc\n";
  for (int k = 0; k <= 120; ++k)
    inputs += fmt::format("{},{},{}\n", 60 * k, 3.0 + 2.0 * std::sin(k / 9.0), k < 50 ? 0.0 : 4.0);
  dir.write("inputs.csv", inputs);
  std::string text = fill(kModel, "", true);
  const auto swap = [&](const std::string& from, const std::string& to) {
    const auto p = text.find(from);
    REQUIRE(p != std::string::npos);
    text.replace(p, from.size(), to);
  };
  swap("heater q a P = 0", "heater q a P = table(\"inputs.csv\", \"Qa\")");
  swap("heater r c P = 0", "heater r c P = table(\"inputs.csv\", \"Qc\")");
  swap("q.P = step(0: 5, 3000: 1); r.P = 2", "initial = 20");
  swap("q.P = 2; r.P = step(0: 0, 1800: 4)", "initial = 20");
  test::LoadedModel m(dir.write("model.tnet", text), test::Lint::clean);
  DiagnosisOptions opt;
  opt.threads = 1;
  const Engine engine(*m.model, opt);
  std::vector<std::unique_ptr<Hypothesis>> owned;
  int checked = 0;
  for (const char* name : {"heater_gain", "input_split", "heater_mass"}) {
    owned.push_back(HypothesisRegistry::global().find(name)->create());
    const Hypothesis* h = owned.back().get();
    for (const Candidate& c : h->propose(engine.evidence())) {
      if (c.start.empty()) continue;
      check_entry(engine, Entry{h, c, h, c, {}}, engine.declared(),
                  fmt::format("{} [{}] {}", c.kind, fmt::join(c.nodes, ", "), c.element));
      ++checked;
    }
  }
  CHECK(checked >= 3);
  // and on top of an applied gain of one heater (the house's second finding before its third)
  const Hypothesis* gain = owned[0].get();
  const Hypothesis* split = owned[1].get();
  const std::vector<Candidate> gains = gain->propose(engine.evidence());
  REQUIRE(!gains.empty());
  const Base base = engine.make_base({Applied{gain, gains.front(), {0.6}}});
  for (const Hypothesis* h : {split, gain})
    for (const Candidate& c : h->propose(engine.evidence()))
      check_entry(engine, Entry{h, c, h, c, {}}, base,
                  fmt::format("{} {} on a gain of {}", c.kind, c.element, gains.front().element));
}
