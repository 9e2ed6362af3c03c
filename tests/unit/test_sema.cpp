/// Unit tests of the semantic pass: every statement of the spec through Model::from_text/load and
/// instantiate() (values in SI, defaults, composites, cases), and every lint check by its code.

#include "kernel/core/element_registry.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "spec_example.hpp"
#include "temp_dir.hpp"

using thermnet::test::TempDir;

using namespace thermnet;
using namespace thermnet::lang;

namespace {

namespace fs = std::filesystem;

/// A model loaded from text, with its sources and diagnostics (not movable).
struct Loaded {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  std::unique_ptr<Model> model;

  Loaded(const std::string& text, const std::string& path) {
    model = Model::from_text(path, text, thermnet::element_catalog(), sources, diags);
  }
  Loaded(const Loaded&) = delete;

  /// Lints and returns the codes of all diagnostics (sorted by position).
  std::vector<std::string> lint() {
    model->lint(diags);
    diags.sort();
    std::vector<std::string> out;
    for (const auto& d : diags.all())
      out.push_back(d.code);
    return out;
  }
  /// True when a diagnostic with this code was reported.
  bool has(const std::string& code) const {
    return std::any_of(diags.all().begin(), diags.all().end(),
                       [&](const Diagnostic& d) { return d.code == code; });
  }
};

std::unique_ptr<Loaded> load(const std::string& text, const std::string& path = "m.tnet") {
  return std::make_unique<Loaded>(text, path);
}

/// The codes lint reports for a model (joined by spaces, for readable failures).
std::string lint_codes(const std::string& text, const std::string& path = "m.tnet") {
  auto m = load(text, path);
  std::string out;
  for (const auto& c : m->lint())
    out += (out.empty() ? "" : " ") + c;
  return out;
}

const ElementSpec& element(const NetworkSpec& net, const std::string& name) {
  for (const auto& e : net.elements)
    if (e.name == name) return e;
  FAIL("no element " << name);
  throw std::logic_error("unreachable");
}

const NodeSpec& node(const NetworkSpec& net, const std::string& name) {
  int i = net.node_index(name);
  REQUIRE(i >= 0);
  return net.nodes[static_cast<std::size_t>(i)];
}

/// A small valid model to which each lint test adds one problem.
const std::string kBase = "boundary amb T = 20\nnode n C = 1\nconductance g n amb G = 1\n";

} // namespace

// -----------------------------------------------------------------------------------------
// Statements through load + instantiate

TEST_CASE("sema: the spec's example instantiates with every value in SI") {
  TempDir dir;
  dir.write("warmup.csv", "time,plate1,plate2,ambient\n0,20,20,20\n60,21,20.5,\n");
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto model = Model::load(dir.write("ex.tnet", test::spec_example), thermnet::element_catalog(),
                           sources, diags);
  REQUIRE(model);
  model->lint(diags);
  CHECK(diags.all().empty());
  CHECK(model->name() == "two_plates");
  CHECK(model->case_names() == std::vector<std::string>{"warmup"});

  NetworkSpec net = model->instantiate();
  CHECK(net.model == "two_plates");
  REQUIRE(net.nodes.size() == 3);
  const NodeSpec& amb = node(net, "ambient");
  CHECK(amb.boundary);
  CHECK(amb.T.kind() == Signal::Kind::pwl);
  CHECK(amb.T.times() == std::vector<double>{0, 2750});
  REQUIRE(amb.T.values().size() == 2);
  CHECK(amb.T.values()[0] == doctest::Approx(293.15));
  CHECK(amb.T.values()[1] == doctest::Approx(238.15));
  const NodeSpec& p1 = node(net, "plate1");
  CHECK(p1.C == 450);
  CHECK_FALSE(p1.T0.has_value());
  CHECK(node(net, "plate2").T0.value() == doctest::Approx(293.15));

  const ElementSpec& gap = element(net, "gap");
  CHECK(std::vector<int>(gap.nodes().begin(), gap.nodes().end()) ==
        std::vector<int>{net.node_index("plate1"), net.node_index("plate2")});
  CHECK(gap.number("h") == 4);
  CHECK(gap.number("A") == doctest::Approx(0.02));
  const ElementSpec& rad = element(net, "rad");
  CHECK(rad.number("F") == 1); // default filled in
  CHECK(rad.number("eps1") == doctest::Approx(0.85));
  const ElementSpec& mount = element(net, "mount");
  CHECK(mount.composite() == Composite::series);
  REQUIRE(mount.parts().size() == 2);
  CHECK(mount.parts()[0].kind() == "contact");
  CHECK(mount.parts()[0].number("A") == doctest::Approx(30e-4));
  CHECK(mount.parts()[1].kind() == "conduction");
  CHECK(mount.parts()[1].number("L") == doctest::Approx(0.003));
  CHECK(mount.parts()[1].number("A") == doctest::Approx(54.8e-6));
  CHECK(std::ranges::equal(mount.parts()[1].nodes(), mount.nodes()));

  // The case: duration in seconds, the override applied, the data file resolved.
  CHECK(net.settings.name == "warmup");
  CHECK(net.settings.duration.value() == doctest::Approx(10800));
  const ElementSpec& film = element(net, "film");
  CHECK(film.values.at("P").kind() == Signal::Kind::step);
  CHECK(film.values.at("P").times() == std::vector<double>{0, 2500});
  CHECK(film.values.at("P").values() == std::vector<double>{10, 0});
  CHECK(fs::path(net.settings.data_path).filename() == "warmup.csv");
  CHECK(net.default_initial() == doctest::Approx(293.15));

  auto params = model->params();
  REQUIRE(params.size() == 1);
  CHECK(params[0].name == "h_gap");
  CHECK(params[0].value == 4);
  CHECK(params[0].lo.value() == 1);
  CHECK(params[0].hi.value() == 10);
  CHECK(params[0].doc == "gas gap convection");

  // A param value given by calibration replaces the declared one.
  NetworkSpec tuned = model->instantiate("warmup", {{"h_gap", 7.5}});
  CHECK(element(tuned, "gap").number("h") == 7.5);
}

TEST_CASE("sema: bare temperatures are degC, bare times are seconds, units convert") {
  auto m = load("boundary a T = 20\nboundary b T = 20 [degC]\nboundary c T = 293.15 [K]\n"
                "node n C = 1.5 [kJ/K] T0 = 68 [degF]\nconductance g n a G = 2\n"
                "conductance g2 n b G = 1\nconductance g3 n c G = 1\n"
                "thermostat t n P = 5 on = 18 off = 22\n"
                "case c {\n  duration = 1.5 [h]\n  output = 30\n  initial = 25\n}\n"
                "case d {\n  duration = 100\n}\n");
  CHECK(m->lint().empty());
  NetworkSpec net = m->model->instantiate("c");
  for (const char* b : {"a", "b", "c"})
    CHECK(node(net, b).T.constant == doctest::Approx(293.15));
  CHECK(node(net, "n").C == doctest::Approx(1500));
  CHECK(node(net, "n").T0.value() == doctest::Approx(293.15));
  CHECK(element(net, "t").number("on") == doctest::Approx(291.15));
  CHECK(net.settings.duration.value() == doctest::Approx(5400));
  CHECK(net.settings.output.value() == 30);
  CHECK(net.settings.initial.value() == doctest::Approx(298.15));
  CHECK(m->model->instantiate("d").settings.duration.value() == 100);
  auto cold = load(kBase + "case c {\n  duration = 1\n  initial = -10 [degC]\n  amb.T = -10\n}\n");
  CHECK(cold->lint().empty());
  NetworkSpec net2 = cold->model->instantiate();
  CHECK(net2.settings.initial.value() == doctest::Approx(263.15));
  CHECK(node(net2, "amb").T.constant == doctest::Approx(263.15));
}

TEST_CASE("sema: const and param references in any order, functions, pi") {
  auto m = load("node n C = a * 2\nconst a = b + 1\nconst b = sqrt(16) + max(1, 2) + pi - pi\n"
                "param r = 2 [mm]\nboundary amb T = 20\n"
                "cylinder_conduction cy n amb k = 1 r_in = r r_out = 2 * r L = 1 [m]\n");
  CHECK(m->lint().empty());
  NetworkSpec net = m->model->instantiate();
  CHECK(node(net, "n").C == doctest::Approx(14));
  CHECK(element(net, "cy").number("r_out") == doctest::Approx(0.004));
  CHECK(net.settings.name == "default");
}

TEST_CASE("sema: case overrides of elements, boundaries, nodes and fixed params") {
  auto m = load("param h_fix = 2 [W/(m^2*K)]\nparam h_cal = 4 range 1 .. 10\n"
                "boundary ambient T = 20\nnode plate C = 450 T0 = 10\n"
                "convection loss plate ambient h = h_fix A = 0.5\n"
                "convection cal plate ambient h = h_cal A = 0.5\nheater film plate P = 10\n"
                "case base { duration = 10 }\n"
                "case hot {\n  duration = 10\n  film.P = step(0: 10, 5: 0)\n"
                "  ambient.T = pwl(0: 20, 10 [min]: 30)\n  h_fix = 3\n  plate.T0 = 30\n"
                "  plate.C = 500 [J/K]\n  loss.A = 0.25\n  initial = steady\n}\n");
  CHECK(m->lint().empty());
  NetworkSpec base = m->model->instantiate("base");
  CHECK(element(base, "loss").number("h") == 2);
  CHECK(element(base, "film").values.at("P").is_constant());
  CHECK_FALSE(base.settings.initial_steady);
  NetworkSpec hot = m->model->instantiate("hot");
  CHECK(element(hot, "loss").number("h") == 3);
  CHECK(element(hot, "loss").number("A") == 0.25);
  CHECK(element(hot, "cal").number("h") == 4);
  CHECK(element(hot, "film").values.at("P").kind() == Signal::Kind::step);
  const NodeSpec& amb = node(hot, "ambient");
  CHECK(amb.T.kind() == Signal::Kind::pwl);
  CHECK(amb.T.times() == std::vector<double>{0, 600});
  CHECK(amb.T.values()[1] == doctest::Approx(303.15));
  CHECK(node(hot, "plate").T0.value() == doctest::Approx(303.15));
  CHECK(node(hot, "plate").C == 500);
  CHECK(hot.settings.initial_steady);
}

TEST_CASE("sema: lint's networks of cases are those instantiate builds (base network shared)") {
  // Two cases set no param (they take the network lint built for the base model, the first a
  // copy, the last the original), one sets a param (elaborated on its own).
  const std::string text = "param h_fix = 2 [W/(m^2*K)]\nboundary ambient T = 20\n"
                           "node plate C = 450 T0 = 10\n"
                           "convection loss plate ambient h = h_fix A = 0.5\n"
                           "heater film plate P = 10\n"
                           "case a { duration = 10\n  loss.A = 0.25\n  plate.T0 = 30 }\n"
                           "case b { duration = 20\n  film.P = step(0: 10, 5: 0) }\n"
                           "case c { duration = 30\n  h_fix = 3 }\n";
  auto linted = load(text);
  CHECK(linted->lint().empty());
  auto fresh = load(text); // never linted: instantiate() elaborates each case itself
  for (const std::string c : {"a", "b", "c"}) {
    CAPTURE(c);
    const NetworkSpec cached = *linted->model->network(c);
    const NetworkSpec own = fresh->model->instantiate(c);
    CHECK(cached.settings.duration == own.settings.duration);
    CHECK(node(cached, "plate").T0 == node(own, "plate").T0);
    for (const char* key : {"h", "A"})
      CHECK(element(cached, "loss").number(key) == element(own, "loss").number(key));
    CHECK(element(cached, "film").values.at("P").kind() ==
          element(own, "film").values.at("P").kind());
  }
  CHECK(element(*linted->model->network("a"), "loss").number("A") == 0.25);
  CHECK(element(*linted->model->network("b"), "loss").number("A") == 0.5);
  CHECK(element(*linted->model->network("c"), "loss").number("h") == 3);
}

TEST_CASE("sema: parallel blocks, radiation by GR, thermostat sense, table signals") {
  TempDir dir;
  dir.write("p.csv", "time,P\n0,10\n100,\n200,0\n");
  std::string path = dir.write("m.tnet", "boundary amb T = 20\nnode a C = 1\nnode b C = 1\n"
                                         "parallel p a amb { conductance G = 1 ; resistor R = 2 }\n"
                                         "radiation r b amb GR = 1e-3\n"
                                         "thermostat t a P = 5 on = 18 off = 22 sense = b\n"
                                         "heater h b P = table(\"p.csv\", \"P\")\n"
                                         "conductance g a b G = 1\n");
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto model = Model::load(path, thermnet::element_catalog(), sources, diags);
  REQUIRE(model);
  model->lint(diags);
  CHECK(diags.all().empty());
  NetworkSpec net = model->instantiate();
  const ElementSpec& p = element(net, "p");
  CHECK(p.composite() == Composite::parallel);
  REQUIRE(p.parts().size() == 2);
  CHECK(p.parts()[1].number("R") == 2);
  CHECK(element(net, "r").number("GR") == doctest::Approx(1e-3));
  CHECK(element(net, "t").node_key("sense") == net.node_index("b"));
  const Signal& s = element(net, "h").values.at("P");
  CHECK(s.kind() == Signal::Kind::pwl);
  CHECK(s.times() == std::vector<double>{0, 200}); // the empty cell is skipped, not zero
  CHECK(s.values() == std::vector<double>{10, 0});
}

TEST_CASE("sema: includes are relative to the including file and read once") {
  TempDir dir;
  dir.write("sub/parts.tnet", "include \"consts.tnet\"\nnode plate C = 450\n");
  dir.write("sub/consts.tnet", "const k = 0.5 [W/K]\n");
  dir.write("sub/other.tnet", "include \"consts.tnet\"\nnode arm C = 5\n");
  // Two files sharing a library read it once, silently.
  std::string shared = dir.write("shared.tnet", "include \"sub/parts.tnet\"\ninclude "
                                                "\"sub/other.tnet\"\nboundary amb T = 20\n"
                                                "conductance g plate amb G = k\n"
                                                "conductance g2 arm amb G = k\n");
  {
    SourceManager sources;
    DiagnosticEngine diags(sources);
    auto model = Model::load(shared, thermnet::element_catalog(), sources, diags);
    REQUIRE(model);
    model->lint(diags);
    CHECK(diags.all().empty());
    CHECK(sources.size() == 4);
    CHECK(element(model->instantiate(), "g").number("G") == 0.5);
  }
  // One file including the same file twice most likely wanted two copies: a warning says that
  // it is read once (submodels make copies).
  std::string twice = dir.write("m.tnet", "include \"sub/parts.tnet\"\ninclude \"sub/parts.tnet\"\n"
                                          "boundary amb T = 20\nconductance g plate amb G = k\n");
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto model = Model::load(twice, thermnet::element_catalog(), sources, diags);
  REQUIRE(model);
  model->lint(diags);
  REQUIRE(diags.all().size() == 1);
  CHECK(diags.all()[0].code == "repeated-include");
  CHECK(diags.all()[0].severity == Severity::warning);
  CHECK(sources.size() == 3);
  CHECK(element(model->instantiate(), "g").number("G") == 0.5);
}

TEST_CASE("sema: instantiate throws ModelError at the first error, with its code") {
  auto m = load(kBase + "conductance g2 n amb G = -1\n");
  try {
    m->model->instantiate();
    FAIL("no ModelError");
  } catch (const ModelError& e) {
    CHECK(e.diag.code == "invalid-value");
  }
  auto two = load(kBase + "case a { duration = 1 }\ncase b { duration = 1 }\n");
  CHECK_THROWS_AS(two->model->instantiate(), ModelError);
  CHECK(two->model->resolve_case("b") == "b");
  CHECK_THROWS_AS(two->model->resolve_case("c"), ModelError);
  // Several cases, one called `default`: it is the one used without --case (cli.md).
  auto with_default = load(kBase + "case a { duration = 1 }\ncase default { duration = 2 }\n");
  CHECK(with_default->model->resolve_case("") == "default");
}

// -----------------------------------------------------------------------------------------
// Lint checks, by code

TEST_CASE("lint: a valid model has no diagnostic") {
  CHECK(lint_codes(kBase) == "");
}

TEST_CASE("lint: each check reports its code") {
  struct Case {
    std::string text;
    const char* codes;
  };
  const Case cases[] = {
      // syntax
      {kBase + "node b C 1\n", "syntax"},
      {kBase + "case c {\n duration = 1\n", "unterminated-block"},
      // names
      {kBase + "conductance g2 n nn G = 1\n", "unknown-node"},
      {kBase + "conductance g2 n amb G = x\n", "unknown-name"},
      {kBase + "conductance g2 n amb G = sqr(2)\n", "unknown-function"},
      {kBase + "conducton g2 n amb G = 1\n", "unknown-kind"},
      {kBase + "conductance g2 n amb GG = 1\n", "unknown-key missing-key"},
      {kBase + "node n C = 2\n", "duplicate-name"},
      {kBase + "node amb C = 2\n", "duplicate-name"},
      {kBase + "conductance g n amb G = 1\n", "duplicate-name"},
      {kBase + "const x = 1\nparam x = 1\nnode m C = x\nconductance g2 m amb G = 1\n",
       "duplicate-name"},
      {kBase + "const pi = 3\n", "duplicate-name"},
      {kBase + "case c { duration = 1 }\ncase c { duration = 1 }\n", "duplicate-name"},
      {"model a\nmodel b\n" + kBase, "duplicate-model"},
      {kBase + "conductance g2 n amb G = 1 G = 2\n", "duplicate-key"},
      {kBase + "conduction g2 n amb k = 1 L = 1\n", "missing-key"},
      {kBase + "radiation r n amb F = 1\n",
       "missing-key missing-key missing-key"}, // F: the A/eps form
      {kBase + "node m\nconductance g2 m amb G = 1\n", "missing-key"},
      {kBase + "radiation r n amb GR = 1 A = 1 eps1 = 1 eps2 = 1\n", "conflicting-keys"},
      {kBase + "cylinder_conduction c n amb k = 1 r_in = 2 r_out = 1 L = 1\n", "conflicting-keys"},
      {kBase + "cylinder_conduction c n amb k = 1 r_in = 1 r_out = 1 L = 1\n", "conflicting-keys"},
      {kBase + "conductance g2 n G = 1\n", "wrong-terminals"},
      {kBase + "conductance g2 n n G = 1\n", "self-link"},
      {kBase + "const a = b\nconst b = a\nnode m C = a\nconductance g2 m amb G = 1\n", "cycle"},
      {kBase + "param p = 1 range 0 .. p\nnode m C = p\nconductance g2 m amb G = 1\n", "cycle"},
      {kBase + "param p = 1 range q .. 2\nconst q = p - 1\nnode m C = p\n"
               "conductance g2 m amb G = 1\n",
       "cycle"},
      {kBase + "heater h amb P = 1\n", "source-on-boundary"},
      {kBase + "thermostat t amb P = 1 on = 1 off = 2\n", "source-on-boundary"},
      // units and values
      {kBase + "node m C = 1 [W/K]\nconductance g2 m amb G = 1\n", "unit-mismatch"},
      {kBase + "conductance g2 n amb G = 1 [m] + 1 [s]\n", "unit-mismatch"},
      {kBase + "conductance g2 n amb G = 1 [Wx]\n", "unknown-unit"},
      {kBase + "conductance g2 n amb G = sqrt(2 [m])\n", "bad-argument"},
      {kBase + "conductance g2 n amb G = 1 / 0\n", "invalid-value"},
      {kBase + "node m C = -1\nconductance g2 m amb G = 1\n", "invalid-value"},
      {kBase + "node m C = 0\nconductance g2 m amb G = 1\n", ""},
      {kBase + "resistor r n amb R = 0\n", "invalid-value"},
      {kBase + "conductance g2 n amb G = -1\n", "invalid-value"},
      {kBase + "conduction c n amb k = 1 L = 0 A = 1\n", "invalid-value"},
      {kBase + "conduction c n amb k = 1 L = 1 A = -1\n", "invalid-value"},
      {kBase + "radiation r n amb A = 1 eps1 = 1.1 eps2 = 1\n", "invalid-value"},
      {kBase + "radiation r n amb A = 1 eps1 = 1 eps2 = 0\n", "invalid-value"},
      {kBase + "radiation r n amb A = 1 eps1 = 1 eps2 = 1\n", ""},
      {kBase + "node m C = 1 T0 = -300\nconductance g2 m amb G = 1\n", "invalid-value"},
      {kBase + "param p = 12 range 1 .. 10\nnode m C = p\nconductance g2 m amb G = 1\n",
       "param-out-of-range"},
      {kBase + "param p = 5 range 10 .. 1\nnode m C = p\nconductance g2 m amb G = 1\n",
       "bad-range"},
      {kBase + "conductance g2 n amb G = step(0: 1)\n", "signal-not-allowed"},
      {kBase + "heater h n P = step(0: 1, 0: 2)\n", "bad-signal"},
      // cases
      {kBase + "case c { initial = 20 }\n", "missing-duration"},
      {kBase + "case c { duration = 1 ; duration = 2 }\n", "duplicate-key"},
      {kBase + "case c { duration = 1 ; nope.P = 1 }\n", "unknown-element"},
      {kBase + "case c { duration = 1 ; g.Q = 1 }\n", "unknown-key"},
      {kBase + "case c { duration = 1 ; amb.C = 1 }\n", "unknown-key"},
      {kBase + "case c { duration = 1 ; nope = 1 }\n", "unknown-element"},
      {kBase + "param p = 1 range 0 .. 2\nnode m C = p\nconductance g2 m amb G = 1\n"
               "case c { duration = 1 ; p = 1.5 }\n",
       "bad-override"},
      {kBase + "param p = 1\nnode m C = p\nconductance g2 m amb G = 1\n"
               "case c { duration = 1 ; p = 1.5 }\n",
       ""},
      {kBase + "case c { duration = 1 ; data \"nope.csv\" }\n", "data-unreadable"},
      {kBase + "heater h n P = table(\"nope.csv\", \"P\")\n", "data-unreadable"},
      // warnings
      {kBase + "node lonely C = 1\n", "isolated-node"},
      {kBase + "node f1 C = 1\nnode f2 C = 1\nconductance gf f1 f2 G = 1\n", "no-boundary-path"},
      {kBase + "param p = 1\n", "unused-param"},
      {kBase + "const c = 1\n", "unused-const"},
      {kBase + "boundary amb2 T = 1\nconductance gb amb amb2 G = 1\n", "boundary-link"},
      // the file itself
      {std::string("node n C = 1\0\n", 14), "invalid-encoding"},
      {"const x = " + std::string(70, '(') + "1" + std::string(70, ')') + "\n", "nesting-too-deep"},
      {kBase + "include \"nope.tnet\"\n", "include-unreadable"},
      {kBase + "plugin \"x.so\"\n", "plugin-error"},
      {kBase + "series s n amb { heater P = 1 }\n", "bad-composite"},
  };
  for (const auto& c : cases) {
    INFO("model:\n", c.text);
    CHECK(lint_codes(c.text) == c.codes);
  }
}

TEST_CASE("lint: data files: unknown columns, format errors, a bad table column") {
  TempDir dir;
  dir.write("d.csv", "time,n,amb,lid\n0,1,2,3\n");
  dir.write("bad.csv", "time,n\n0,1\n0,2\n");
  dir.write("p.csv", "time,P\n0,1\n");
  auto run = [&](const std::string& text) {
    SourceManager sources;
    DiagnosticEngine diags(sources);
    auto model =
        Model::load(dir.write("m.tnet", text), thermnet::element_catalog(), sources, diags);
    REQUIRE(model);
    model->lint(diags);
    std::string out;
    for (const auto& d : diags.all())
      out += (out.empty() ? "" : " ") + d.code;
    return out;
  };
  CHECK(run(kBase + "case c { duration = 1 ; data \"d.csv\" }\n") == "data-unknown-column");
  CHECK(run(kBase + "case c { duration = 1 ; data \"bad.csv\" }\n") == "data-format");
  CHECK(run(kBase + "heater h n P = table(\"p.csv\", \"Q\")\n") == "bad-signal");
  CHECK(run(kBase + "heater h n P = table(\"p.csv\", \"P\")\n") == "");
  CHECK(run(kBase + "case c { duration = 1 ; data \"/dev/zero\" }\n") == "data-unreadable");
}

TEST_CASE("lint: include cycles and errors inside included files") {
  TempDir dir;
  dir.write("a.tnet", "include \"b.tnet\"\n");
  dir.write("b.tnet", "include \"a.tnet\"\nnode x C = [\n");
  SourceManager sources;
  DiagnosticEngine diags(sources);
  auto model = Model::load(dir.write("a.tnet", "include \"b.tnet\"\n"), thermnet::element_catalog(),
                           sources, diags);
  REQUIRE(model);
  model->lint(diags);
  diags.sort();
  std::vector<std::string> codes;
  for (const auto& d : diags.all()) {
    codes.push_back(d.code);
    REQUIRE(d.at.has_value());
    CHECK(sources.path(d.at->file).find("b.tnet") != std::string::npos);
  }
  CHECK(codes == std::vector<std::string>{"include-cycle", "syntax"});
}

TEST_CASE("lint: a statement with a syntax error hides no other error and adds none") {
  // 'b' and 'x' are declared by broken statements: their uses are not reported again, and the
  // warnings about the network's shape and unused values are left out.
  CHECK(lint_codes("boundary amb T = 20\nnode b C 1\nconst x = (1 +\nnode lonely C = 1\n"
                   "conductance g b amb G = x\nconductance g2 b amb G = 1\nparam unused = 1\n"
                   "case c { duration = 1 ; g2.G = x ; data \"nope.csv\" }\n"
                   "conductance g3 nn amb G = 1\n") ==
        "syntax syntax data-unreadable unknown-node");
}

TEST_CASE("lint: an element with an error still links its nodes (no cascading warnings)") {
  CHECK(lint_codes("boundary amb T = 20\nnode a C = 1\nnode b C = 1\n"
                   "conductance g a amb G = -1\nconduction c b lens3 k = 1 L = 1 A = 1\n") ==
        "invalid-value unknown-node");
}

TEST_CASE("lint: reports are located at the statement, the caret on the offending token") {
  auto m = load("boundary housing T = 25\nnode lens1 C = 1\nnode lens2 C = 1\n"
                "conductance m1 lens1 housing G = 1\nconductance m2 lens2 housing G = 1\n"
                "    conduction g1 lens1 lens3 k = 1 L = 0.01 A = 3e-4\n");
  CHECK(m->lint() == std::vector<std::string>{"unknown-node"});
  const Diagnostic& d = m->diags.all().front();
  LineCol at = m->sources.line_col(d.at->file, d.at->begin);
  CHECK(at.line == 6);
  CHECK(at.column == 5);
  LineCol mark = m->sources.line_col(d.mark->file, d.mark->begin);
  CHECK(mark.column == 25);
  CHECK(d.mark->end - d.mark->begin == 5);
  REQUIRE(d.notes.size() == 1);
  CHECK(d.notes[0].message == "did you mean 'lens2'?");
}

TEST_CASE("lint: the error limit stops lint and says so") {
  std::string text = kBase;
  for (int i = 0; i < 500; ++i)
    text += "conductance x" + std::to_string(i) + " n amb G = nope\n";
  auto m = load(text);
  auto codes = m->lint();
  REQUIRE(!codes.empty());
  CHECK(codes.back() == "too-many-errors");
  CHECK(codes.size() == 201);
}
