/// Unit tests of the language's repeated structure and time: loops and indexed names, submodels,
/// the simulation time in expressions, listed output times and the unit of data files. A model
/// written with loops or submodels must be the very network its hand-written twin is, with the
/// very same results.

#include "kernel/core/element_registry.hpp"
#include "kernel/core/measured_data.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/csv.hpp"
#include "lang/diagnostics.hpp"
#include "lang/loop_iteration.hpp"
#include "lang/model.hpp"
#include "lang/name_list.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "temp_dir.hpp"

using thermnet::test::TempDir;
using namespace thermnet;
using namespace thermnet::lang;

namespace {

/// A model loaded from a file in a scratch folder, linted clean.
struct Clean {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  std::unique_ptr<Model> model;

  Clean(const TempDir& dir, const std::string& name, const std::string& text,
        const LoadOptions& options = {}) {
    model = Model::load(dir.write(name, text), element_catalog(), sources, diags, options);
    REQUIRE(model);
    model->lint(diags);
    INFO(render_text(diags));
    REQUIRE(diags.error_count() == 0);
  }
  Clean(const Clean&) = delete;
};

/// The codes lint reports for a model text, separated by spaces.
std::string lint_codes(const std::string& text, const LoadOptions& options = {}) {
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto model = Model::from_text("m.tnet", text, element_catalog(), sources, diags, options);
  model->lint(diags);
  diags.sort();
  std::string codes;
  for (const auto& d : diags.all())
    codes += (codes.empty() ? "" : " ") + d.code;
  return codes;
}

/// Every signal value a test compares: the kind, corners and values, and samples of the value.
void check_same_signal(const Signal& a, const Signal& b) {
  CHECK(a.kind() == b.kind());
  CHECK(a.constant == b.constant);
  CHECK(a.times() == b.times());
  CHECK(a.values() == b.values());
  for (double t : {0.0, 17.0, 600.0, 3599.0})
    CHECK(a.at(t) == b.at(t));
}

/// Two networks are the same: nodes and elements in the same order with the same values; names
/// compared after `rename` is applied to the first network's names.
void check_same_network(const NetworkSpec& a, const NetworkSpec& b,
                        std::string (*rename)(const std::string&)) {
  REQUIRE(a.nodes.size() == b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    INFO("node ", a.nodes[i].name);
    CHECK(rename(a.nodes[i].name) == b.nodes[i].name);
    CHECK(a.nodes[i].boundary == b.nodes[i].boundary);
    CHECK(a.nodes[i].C == b.nodes[i].C);
    CHECK(a.nodes[i].T0 == b.nodes[i].T0);
    check_same_signal(a.nodes[i].T, b.nodes[i].T);
  }
  REQUIRE(a.elements.size() == b.elements.size());
  for (std::size_t i = 0; i < a.elements.size(); ++i) {
    const ElementSpec& x = a.elements[i];
    const ElementSpec& y = b.elements[i];
    INFO("element ", x.name);
    CHECK(rename(x.name) == y.name);
    CHECK(x.kind() == y.kind());
    CHECK(std::ranges::equal(x.nodes(), y.nodes()));
    REQUIRE(x.values.size() == y.values.size());
    for (const auto& [key, s] : x.values) {
      REQUIRE(y.values.count(key) == 1);
      check_same_signal(s, y.values.at(key));
    }
  }
  CHECK(a.settings.duration == b.settings.duration);
  CHECK(a.settings.output_times == b.settings.output_times);
}

std::string same(const std::string& s) {
  return s;
}

/// The temperatures of two runs are identical, every node at every time.
void check_same_results(const NetworkSpec& a, const NetworkSpec& b) {
  Network na(a), nb(b);
  SimulationResult ra = simulate(na), rb = simulate(nb);
  REQUIRE(ra.times == rb.times);
  CHECK(ra.temps == rb.temps);
}

const char* const kPanelLoops = R"(model panel
const n = 6
boundary space T = -270
boundary frame T = 20
for i in 1 .. n, j in 1 .. n {
  node p[i, j] C = (5 + 0.1 * i) * 1 [J/K] T0 = 20
  radiation r[i, j] p[i, j] space A = 0.01 eps1 = 0.8 eps2 = 1
}
for i in 1 .. n - 1 {
  for j in 1 .. n {
    conductance gx[i, j] p[i, j] p[i + 1, j] G = 0.4
    conductance gy[j, i] p[j, i] p[j, i + 1] G = 0.4
  }
}
for j in 1 .. n {
  series m[j] p[1, j] frame { contact h = 2000 A = 1e-4 ; conductance G = 0.2 }
}
heater h p[3, 4] P = 4 + sin(time / 300)
case run {
  duration = 1 [h]
  output = 0, 60, 600, 3600
  for i in 2 .. 3 { p[i, i].T0 = 25 }
}
)";

/// The same panel with every iteration written out by hand.
std::string panel_flat() {
  const int n = 6;
  std::string t = "model panel\nboundary space T = -270\nboundary frame T = 20\n";
  for (int i = 1; i <= n; ++i)
    for (int j = 1; j <= n; ++j)
      t += fmt::format("node p[{0},{1}] C = (5 + 0.1 * {0}) * 1 [J/K] T0 = 20\n"
                       "radiation r[{0},{1}] p[{0},{1}] space A = 0.01 eps1 = 0.8 eps2 = 1\n",
                       i, j);
  for (int i = 1; i < n; ++i)
    for (int j = 1; j <= n; ++j)
      t += fmt::format("conductance gx[{0},{1}] p[{0},{1}] p[{2},{1}] G = 0.4\n"
                       "conductance gy[{1},{0}] p[{1},{0}] p[{1},{2}] G = 0.4\n",
                       i, j, i + 1);
  for (int j = 1; j <= n; ++j)
    t += fmt::format(
        "series m[{0}] p[1,{0}] frame {{ contact h = 2000 A = 1e-4 ; conductance G = 0.2 }}\n", j);
  t += "heater h p[3,4] P = 4 + sin(time / 300)\n";
  t += "case run {\n  duration = 1 [h]\n  output = 0, 60, 600, 3600\n  p[2,2].T0 = 25\n"
       "  p[3,3].T0 = 25\n}\n";
  return t;
}

const char* const kBoxes = R"(boundary room T = 20
boundary rack T = 25 - 0.0005 * time
param h_wall = 3 [W/(m^2*K)] range 1 .. 10
submodel box(mount) {
  param P = 5 [W]
  param area = 0.06 [m^2]
  const wall_C = 900 [J/K]
  node wall C = wall_C
  node pcb C = 150 [J/K]
  node air C = 20 [J/K]
  convection in_wall air wall h = 4 A = area
  convection in_pcb air pcb h = 4 A = area / 3
  conductance standoffs pcb mount G = 0.05
  convection out wall mount h = h_wall A = area
  heater heat pcb P = P
}
box u1 rack P = 8
box u2 rack P = 5 area = 0.08 [m^2]
box u3 room
box u4 room P = 12
case run {
  duration = 2 [h]
  output = 600
  u4.heat.P = step(0: 12, 3600: 0)
  u2.pcb.T0 = 30
}
)";

/// The four boxes by hand, named with '_' where the instances name with '.'.
std::string boxes_flat() {
  std::string t = "boundary room T = 20\nboundary rack T = 25 - 0.0005 * time\n"
                  "param h_wall = 3 [W/(m^2*K)] range 1 .. 10\n";
  struct Box {
    const char* name;
    const char* mount;
    const char* P;
    const char* area;
  };
  const Box boxes[] = {{"u1", "rack", "8", "0.06 [m^2]"},
                       {"u2", "rack", "5", "0.08 [m^2]"},
                       {"u3", "room", "5 [W]", "0.06 [m^2]"},
                       {"u4", "room", "12", "0.06 [m^2]"}};
  for (const Box& b : boxes)
    t += fmt::format("node {0}_wall C = 900 [J/K]\nnode {0}_pcb C = 150 [J/K]\n"
                     "node {0}_air C = 20 [J/K]\n"
                     "convection {0}_in_wall {0}_air {0}_wall h = 4 A = {3}\n"
                     "convection {0}_in_pcb {0}_air {0}_pcb h = 4 A = {3} / 3\n"
                     "conductance {0}_standoffs {0}_pcb {1} G = 0.05\n"
                     "convection {0}_out {0}_wall {1} h = h_wall A = {3}\n"
                     "heater {0}_heat {0}_pcb P = {2}\n",
                     b.name, b.mount, b.P, b.area);
  t += "case run {\n  duration = 2 [h]\n  output = 600\n  u4_heat.P = step(0: 12, 3600: 0)\n"
       "  u2_pcb.T0 = 30\n}\n";
  return t;
}

std::string dots_to_underscores(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (c == '.') c = '_';
  return out;
}

} // namespace

TEST_CASE("loops: a panel written with loops is the panel written flat, with the same results") {
  TempDir dir;
  Clean loops(dir, "loops.tnet", kPanelLoops);
  Clean flat(dir, "flat.tnet", panel_flat());
  NetworkSpec a = loops.model->instantiate("run"), b = flat.model->instantiate("run");
  CHECK(a.nodes.size() == 2 + 36);
  CHECK(a.elements.size() == 36 + 2 * 30 + 6 + 1);
  CHECK(a.nodes[a.node_index("p[2,2]")].T0.value() == doctest::Approx(298.15));
  check_same_network(a, b, same);
  check_same_results(a, b);
}

TEST_CASE("submodels: four instances are the parts written by hand, with the same results") {
  TempDir dir;
  Clean boxes(dir, "boxes.tnet", kBoxes);
  Clean flat(dir, "flat.tnet", boxes_flat());
  NetworkSpec a = boxes.model->instantiate("run"), b = flat.model->instantiate("run");
  check_same_network(a, b, dots_to_underscores);
  check_same_results(a, b);
  // A top-level ranged param passed into the instances stays calibratable, for all of them.
  auto params = boxes.model->params();
  REQUIRE(params.size() == 1);
  NetworkSpec tuned = boxes.model->instantiate("run", {{"h_wall", 6.0}});
  for (const auto& e : tuned.elements)
    if (e.name.ends_with(".out")) CHECK(e.number("h") == 6.0);
}

TEST_CASE("submodels: inner names serve cases, data columns and node lists") {
  TempDir dir;
  dir.write("run.csv", "time,u1.pcb,\"u2.air\"\n0,20,20\n600,31.5,24\n");
  Clean m(
      dir, "boxes.tnet",
      std::string(kBoxes).replace(std::string(kBoxes).find("  output"), 0, "  data \"run.csv\"\n"));
  NetworkSpec net = m.model->instantiate("run");
  CHECK(net.nodes[net.node_index("u2.pcb")].T0.value() == doctest::Approx(303.15));
  MeasuredData data = load_measured(net.settings.data_path, net);
  REQUIRE(data.series.size() == 2);
  CHECK(data.series[0].node_index == net.node_index("u1.pcb"));
  CHECK(data.series[1].node_index == net.node_index("u2.air"));
  CHECK(join_bracketed({"p[1", "2]", "u1.pcb", "q[3", "4", "5]"}) ==
        std::vector<std::string>{"p[1,2]", "u1.pcb", "q[3,4,5]"});
}

TEST_CASE("submodels: nested instances, a const from the instance's params, terminals passed on") {
  TempDir dir;
  Clean m(dir, "nested.tnet", R"(boundary amb T = 20
submodel leg(top, bottom) {
  param G = 1
  const R = 1 / G
  resistor r top bottom R = R
}
submodel table(floor) {
  param n = 4
  node plate C = 100
  for k in 1 .. n { leg l[k] plate floor G = k }
}
table t1 amb
table t2 amb n = 2
)");
  NetworkSpec net = m.model->instantiate();
  CHECK(net.node_index("t1.plate") >= 0);
  int legs = 0;
  for (const auto& e : net.elements) {
    if (e.kind() != "resistor") continue;
    ++legs;
    const char k = e.name[e.name.find('[') + 1];
    CHECK(e.number("R") == doctest::Approx(1.0 / (k - '0')));
    CHECK(e.nodes()[1] == net.node_index("amb"));
  }
  CHECK(legs == 6);
  CHECK(m.model->network()->elements.size() == 6);
}

TEST_CASE("loops: ranges may use outer variables, consts and instance params; not params") {
  CHECK(lint_codes("boundary a T = 0\nfor i in 1 .. 3 {\n  for j in i .. 3 {\n    node p[i, j] "
                   "C = 1\n    conductance g[i, j] p[i, j] a G = 1\n  }\n}\n") == "");
  CHECK(lint_codes("param n = 3\nboundary a T = 0\nfor i in 1 .. n { node p[i] C = 1 }\n") ==
        "param-in-structure");
  // An empty range declares nothing.
  CHECK(lint_codes("boundary a T = 0\nnode p[1 .. 0] C = 1\nfor i in 3 .. 1 { node q C = 1 }\n") ==
        "");
}

TEST_CASE("loops: a loop that asks for too much stops with an error, not a hang") {
  LoadOptions small;
  small.max_generated = 1000;
  CHECK(lint_codes("for i in 1 .. 1000000000 {\n}\n", small) == "too-large");
  CHECK(lint_codes("node p[1 .. 100000, 1 .. 100000] C = 1\n", small) == "too-large");
  CHECK(lint_codes("submodel a(x) { node n C = 1\nconductance g n x G = 1 }\nboundary b T = 0\n"
                   "for i in 1 .. 5000 { a u[i] b }\n",
                   small) == "too-large");
}

TEST_CASE("loops: a case's loops run at most LoadOptions::max_case_iterations times in all") {
  // Each range counts its values: 10 of i, then 10 times the n of j.
  LoadOptions small;
  small.max_case_iterations = 110;
  const auto model = [](int n) {
    return fmt::format("boundary b T = 0\nnode p[1 .. 10] C = 1\nfor i in 1 .. 10 {{ conductance "
                       "g[i] p[i] b G = 1 }}\ncase c {{\n  duration = 1\n  for i in 1 .. 10, j "
                       "in 1 .. {} {{ }}\n}}\n",
                       n);
  };
  CHECK(lint_codes(model(10), small) == "");
  CHECK(lint_codes(model(11), small) == "bad-loop");
  CHECK(lint_codes(model(11)) == ""); // the default allows a million
}

TEST_CASE(
    "loops: the iterations of a header without recursion, later ranges using earlier values") {
  // for i in 1 .. 3, j in i .. 3, k in 1 .. j - i: the combinations in order, outermost first.
  std::vector<long> values;
  std::vector<std::string> seen;
  const bool done = for_each_iteration(
      3, values,
      [&](std::size_t k) -> std::optional<LoopBounds> {
        if (k == 0) return LoopBounds{1, 3};
        if (k == 1) return LoopBounds{values[0], 3};
        return LoopBounds{1, values[1] - values[0]};
      },
      [] { return true; },
      [&] {
        seen.push_back(fmt::format("{}", fmt::join(values, "")));
        return true;
      });
  CHECK(done);
  CHECK(seen == std::vector<std::string>{"121", "131", "132", "231"});
  // A million variables of one value each: one iteration, no deep recursion.
  std::size_t steps = 0, bodies = 0;
  CHECK(for_each_iteration(
      1'000'000, values,
      [](std::size_t) {
        return std::optional<LoopBounds>{LoopBounds{7, 7}};
      },
      [&] { return ++steps > 0; }, [&] { return ++bodies > 0; }));
  CHECK(steps == 1'000'000);
  CHECK(bodies == 1);
  // A false from the body stops everything.
  bodies = 0;
  CHECK_FALSE(for_each_iteration(
      2, values,
      [](std::size_t) {
        return std::optional<LoopBounds>{LoopBounds{1, 5}};
      },
      [] { return true; }, [&] { return ++bodies < 3; }));
  CHECK(bodies == 3);
}

TEST_CASE("loops: huge ranges are refused before they run; empty iterations keep no scope") {
  LoadOptions small;
  small.max_generated = 1000;
  // 500 nodes and 500 iterations with one element each: 1500 > 1000, the element range that
  // passes the limit is refused; 300 of each pass.
  const auto grid = [](int n) {
    return fmt::format("boundary b T = 0\nnode p[1 .. {}] C = 1\nfor i in 1 .. {} {{ conductance "
                       "g[i] p[i] b G = 1 }}\n",
                       n, n);
  };
  CHECK(lint_codes(grid(500), small) == "too-large");
  CHECK(lint_codes(grid(300), small) == "");
  CHECK(lint_codes("node p[1 .. 1001] C = 1\n", small) == "too-large");
  CHECK(lint_codes("for i in 1 .. 1001 { }\n", small) == "too-large");
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto m = Model::from_text("m.tnet", "for i in 1 .. 900 { }\n", element_catalog(), sources, diags,
                            small);
  CHECK(m->scopes().empty());
}

TEST_CASE("submodels: a cycle is found where it is defined; chains nest at most 64 deep") {
  CHECK(lint_codes("submodel s(x) {\n  node m C = 1\n  s inner m\n}\n") == "submodel-cycle");
  CHECK(lint_codes("submodel a(x) {\n  for i in 1 .. 2 { b u[i] x }\n}\nsubmodel b(x) {\n  a v x\n}"
                   "\n") == "submodel-cycle");
  // 64 nested instances are fine, 65 are not.
  const auto chain = [](int n) {
    std::string text = "boundary b T = 20\n";
    for (int k = 1; k < n; ++k)
      text += fmt::format("submodel s{}(x) {{\n  s{} i x\n}}\n", k, k + 1);
    text += fmt::format("submodel s{}(x) {{\n  node m C = 1\n  conductance g m x G = 1\n}}\n", n);
    return text + "s1 top b\n";
  };
  CHECK(lint_codes(chain(64)) == "");
  CHECK(lint_codes(chain(65)) == "submodel-too-deep");
}

TEST_CASE("cases: a key set twice, an index past 1e15, an output time past the end") {
  const std::string base = "boundary b T = 20\nnode n[1 .. 2] C = 1\nfor i in 1 .. 2 { conductance "
                           "g[i] n[i] b G = 1 }\nheater h n[1] P = 1\n";
  CHECK(lint_codes(base + "case c {\n  duration = 1\n  h.P = 2\n  n[2].C = 3\n}\n") == "");
  CHECK(lint_codes(base + "case c {\n  duration = 1\n  h.P = 2\n  h.P = 3\n}\n") ==
        "duplicate-key");
  CHECK(lint_codes(base + "case c {\n  duration = 1\n  for i in 1 .. 2 { n[1].C = i }\n}\n") ==
        "duplicate-key");
  CHECK(lint_codes(base + "case c {\n  duration = 1\n  for i in 1 .. 2 { n[i].C = i }\n}\n") == "");
  CHECK(lint_codes(base + "case c {\n  duration = 10\n  output = 0, 5, 10\n}\n") == "");
  CHECK(lint_codes(base + "case c {\n  duration = 10\n  output = 0, 5, 11\n}\n") ==
        "invalid-value");
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto m = Model::from_text("m.tnet", "node p[9007199254740992] C = 1\n", element_catalog(),
                            sources, diags);
  CHECK(render_text(diags).find("an index must lie between -1e15 and 1e15, got 9.0072e+15") !=
        std::string::npos);
}

TEST_CASE("time: a boundary ramp T = T0 + r * time gives the analytic first-order lag") {
  TempDir dir;
  // dT/dt = (T_b - T) / tau with T_b = 20 + r t and T(0) = 20: T = 20 + r (t - tau (1 - e^-t/tau)).
  Clean m(dir, "ramp.tnet", R"(const r = 0.01
boundary b T = 20 + r * time
node n C = 500 [J/K] T0 = 20
conductance g n b G = 2
case run {
  duration = 2000
  output = 0, 123.5, 1000, 2000
}
)");
  NetworkSpec spec = m.model->instantiate("run");
  Network net(spec);
  SimulationOptions opt;
  opt.solver.rtol = opt.solver.atol = 1e-9;
  SimulationResult res = simulate(net, opt);
  REQUIRE(res.times == std::vector<double>{0, 123.5, 1000, 2000});
  const int n = spec.node_index("n"), b = spec.node_index("b");
  const double tau = 250.0, r = 0.01;
  for (std::size_t k = 0; k < res.times.size(); ++k) {
    const double t = res.times[k];
    CHECK(res.temps[k][static_cast<std::size_t>(b)] - 273.15 == doctest::Approx(20 + r * t));
    CHECK(res.temps[k][static_cast<std::size_t>(n)] - 273.15 ==
          doctest::Approx(20 + r * (t - tau * (1 - std::exp(-t / tau)))).epsilon(1e-7));
  }
}

TEST_CASE("time: a declared const, param or loop variable named time keeps its meaning") {
  TempDir dir;
  Clean m(dir, "t.tnet",
          "const time = 5\nboundary b T = 20 + time\nnode n C = 1\n"
          "conductance g n b G = 1\n");
  const NetworkSpec net = m.model->instantiate();
  const Signal& T = net.nodes[static_cast<std::size_t>(net.node_index("b"))].T;
  CHECK(T.is_constant());
  CHECK(T.constant == doctest::Approx(298.15));
}

TEST_CASE("output: listed times are written exactly; an interval still works") {
  TempDir dir;
  Clean m(dir, "o.tnet",
          "boundary b T = 0\nnode n C = 1 T0 = 10\nconductance g n b G = 1\n"
          "case listed { duration = 10\n output = 0, 0.25, 3 [s], 10 }\n"
          "case every { duration = 10\n output = 5 }\n");
  Network listed(m.model->instantiate("listed"));
  CHECK(simulate(listed).times == std::vector<double>{0, 0.25, 3, 10});
  Network every(m.model->instantiate("every"));
  CHECK(simulate(every).times == std::vector<double>{0, 5, 10});
  // A listed time after the case's duration is a lint error; after a shorter --duration, the run
  // is refused.
  CHECK(lint_codes("boundary b T = 0\nnode n C = 1\nconductance g n b G = 1\ncase short { "
                   "duration = 2\n output = 0, 3 }\n") == "invalid-value");
  SimulationOptions shorter;
  shorter.duration = 2.0;
  CHECK_THROWS_AS(simulate(listed, shorter), std::invalid_argument);
}

TEST_CASE("data: a file in kelvin declared [K] reads as the same temperatures as in degC") {
  TempDir dir;
  dir.write("c.csv", "time,n\n0,20\n10,15.5\n");
  dir.write("k.csv", "time,n\n0,293.15\n10,288.65\n");
  dir.write("f.csv", "time,n\n0,68\n10,59.9\n");
  Clean m(dir, "d.tnet",
          "boundary b T = 0\nnode n C = 1 T0 = 20\nconductance g n b G = 1\n"
          "case c { duration = 10\n data \"c.csv\" }\n"
          "case k { duration = 10\n data \"k.csv\" [K] }\n"
          "case f { duration = 10\n data \"f.csv\" [degF] }\n");
  auto values = [&](const std::string& c) {
    NetworkSpec s = m.model->instantiate(c);
    return load_measured(s.settings.data_path, s).series.at(0).values;
  };
  const auto c = values("c"), k = values("k"), f = values("f");
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(k[i] == doctest::Approx(c[i]));
    CHECK(f[i] == doctest::Approx(c[i]));
  }
}

TEST_CASE("data: names with commas read from quoted and bracketed headers") {
  CsvTable t = parse_csv("time,\"p[1,2]\",p[3,4], \"q\"\"x\" \n0,1,2,3\n", "t.csv");
  CHECK(t.columns == std::vector<std::string>{"time", "p[1,2]", "p[3,4]", "q\"x"});
  CHECK(t.cells[2][0] == 2);
}

TEST_CASE("examples: the 10 x 10 panel and the four boxes in models/examples lint clean") {
  const std::string dir = std::string(THERMNET_TEST_DIR) + "/../models/examples/";
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto panel = Model::load(dir + "panel.tnet", element_catalog(), sources, diags);
  auto boxes = Model::load(dir + "boxes.tnet", element_catalog(), sources, diags);
  REQUIRE(panel);
  REQUIRE(boxes);
  panel->lint(diags);
  boxes->lint(diags);
  INFO(render_text(diags));
  CHECK(diags.all().empty()); // no error and no warning
  NetworkSpec p = panel->instantiate("orbit");
  int cells = 0;
  for (const auto& n : p.nodes)
    cells += n.name.starts_with("p[") ? 1 : 0;
  CHECK(cells == 100);
  CHECK(p.node_index("p[10,10]") >= 0);
  NetworkSpec b = boxes->instantiate("flight");
  for (const char* unit : {"radio", "computer", "recorder", "camera"})
    CHECK(b.node_index(std::string(unit) + ".pcb") >= 0);
  CHECK(b.nodes[b.node_index("radio.pcb")].T0.value() == doctest::Approx(303.15));
}
