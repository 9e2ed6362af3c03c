/// Unit tests of the forms that read real test campaigns: signal expressions (`Aw * table(...)`),
/// held and on/off columns, data files in their own layout with a column map, sensors, key
/// references, start temperatures from the data or calibrated per case.

#include "kernel/calibration/calibration_problem.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/core/measured_data.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/csv.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "temp_dir.hpp"

using thermnet::test::TempDir;

using namespace thermnet;
using namespace thermnet::lang;

namespace {

/// A model written to a scratch folder beside its data, loaded and linted.
struct Campaign {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  std::unique_ptr<Model> model;

  Campaign(const TempDir& dir, const std::string& text) {
    const std::string path = dir.write("model.tnet", text);
    model = Model::load(path, thermnet::element_catalog(), sources, diags);
    REQUIRE(model);
    model->lint(diags);
  }
  Campaign(const Campaign&) = delete;
  /// The codes of the problems lint found.
  std::vector<std::string> codes() const {
    std::vector<std::string> out;
    for (const auto& d : diags.all())
      out.push_back(d.code);
    return out;
  }
  /// Requires a clean lint.
  void require_clean() const {
    INFO(render_text(diags));
    REQUIRE(diags.error_count() == 0);
  }
  /// Simulates a case at the given times; temperatures of every node, K.
  SimulationResult run(const std::string& case_name, std::vector<double> times,
                       bool sensors = false) const {
    Network net(model->instantiate(case_name));
    SimulationOptions o;
    o.output = times.size() > 1 ? times[1] - times[0] : 1.0;
    o.duration = times.back();
    o.sensors = sensors;
    o.solver.rtol = 1e-10;
    o.solver.atol = 1e-10;
    return simulate(net, o);
  }
};

const char* kHeatedBox = R"(
param Aw = 2 [m^2] range 1 .. 4
boundary room T = 20
node box C = 1000
conductance g box room G = 2
)";

} // namespace

TEST_CASE("campaign: a pwl written by hand and the same signal through Aw * table() agree") {
  TempDir dir("campaign");
  dir.write("sun.csv", "time,I_sol\n0,0\n600,100\n1800,400\n3600,50\n");
  Campaign by_hand(dir, std::string(kHeatedBox) +
                            "heater sun box P = pwl(0: 0, 600: 200 [W], 1800: 800 [W], "
                            "3600: 100 [W])\ncase c { duration = 1 [h] }\n");
  by_hand.require_clean();
  Campaign by_table(dir, std::string(kHeatedBox) +
                             "heater sun box P = Aw * table(\"sun.csv\", \"I_sol\") [W/m^2]\n"
                             "case c { duration = 1 [h] }\n");
  by_table.require_clean();
  std::vector<double> times;
  for (int k = 0; k <= 60; ++k)
    times.push_back(60.0 * k);
  const auto a = by_hand.run("c", times), b = by_table.run("c", times);
  REQUIRE(a.temps.size() == b.temps.size());
  for (std::size_t k = 0; k < a.temps.size(); ++k)
    CHECK(b.temps[k][1] == doctest::Approx(a.temps[k][1]).epsilon(1e-9));
  // The param stays calibratable: a larger aperture heats more.
  Network more(by_table.model->instantiate("c", {{"Aw", 4.0}}));
  SimulationOptions o;
  o.duration = 3600;
  const auto c = simulate(more, o);
  CHECK(c.temps.back()[1] > b.temps.back()[1] + 1.0);
}

TEST_CASE("campaign: a held on/off column switches a heater and restarts only where it changes") {
  TempDir dir("campaign");
  std::string csv = "time,relay\n";
  int changes = 0;
  bool on = false;
  for (int k = 0; k < 300; ++k) {
    const bool next = (k / 37) % 2 == 1; // switches every 37 rows
    changes += k > 0 && next != on;
    on = next;
    csv += std::to_string(k * 10) + "," + (on ? "True" : "False") + "\n";
  }
  dir.write("relay.csv", csv);
  Campaign m(dir, std::string(kHeatedBox) +
                      "heater h box P = 50 [W] * table(\"relay.csv\", \"relay\", hold)\n"
                      "case c { duration = 2990 }\n");
  m.require_clean();
  Network net(m.model->instantiate("c"));
  SimulationOptions o;
  o.duration = 2990;
  o.output = 10;
  const auto r = simulate(net, o);
  CHECK(r.stats.restarts == changes);
  // Held, not interpolated: the power of row k holds until row k + 1.
  const Signal& P = net.spec().elements.back().values.at("P");
  CHECK(P.at(375.0) == doctest::Approx(50.0)); // rows 37..73 (370 .. 739 s) are on
  CHECK(P.at(739.99) == doctest::Approx(50.0));
  CHECK(P.at(365.0) == doctest::Approx(0.0));
  CHECK(P.at(745.0) == doctest::Approx(0.0));
}

TEST_CASE("campaign: a data file in its own layout, with a column map, UNIX and ISO times") {
  TempDir dir("campaign");
  dir.write("run.csv", "stamp;t_room;a;b;heater_on\n"
                       "1600000000;20;30;32;True\n"
                       "1600000060;20.5;31;33;True\n"
                       "1600000120;21;32;34;False\n");
  Campaign m(dir, std::string(kHeatedBox) +
                      "heater h box P = 10 * table(data, \"heater_on\", hold)\n"
                      "case c {\n  duration = 120\n  initial = data\n"
                      "  data \"run.csv\" time = \"stamp\" [unix s] separator = \";\" {\n"
                      "    box = mean(a, b)\n    room = t_room\n  }\n}\n");
  m.require_clean();
  const NetworkSpec spec = m.model->instantiate("c");
  const MeasuredData d = load_measured(spec.settings.data_path, spec);
  REQUIRE(d.times == std::vector<double>{0, 60, 120});
  REQUIRE(d.series.size() == 2);
  CHECK(d.series[0].node == "box");
  CHECK(d.series[0].values[1] == doctest::Approx(32 + 273.15));
  CHECK(d.series[1].node == "room");
  // The heater reads the same clock: on for the first two rows, off from 120 s.
  const Signal& P = spec.elements.back().values.at("P");
  CHECK(P.at(100) == doctest::Approx(10.0));
  CHECK(P.at(120) == doctest::Approx(0.0));
  // initial = data: the measured node starts at its first measured value.
  REQUIRE(spec.nodes[1].T0);
  CHECK(*spec.nodes[1].T0 == doctest::Approx(31 + 273.15));

  CsvLayout iso;
  iso.time_column = "when";
  iso.time_first = false;
  REQUIRE_FALSE(parse_time_format("iso", iso));
  const CsvTable t = parse_csv("x,when\n1,2021-01-22T14:48:58.5Z\n2,2021-01-22 15:48:59+01:00\n"
                               "3,2021-01-23\n",
                               "t.csv", iso);
  CHECK(t.time()[0] == doctest::Approx(1611326938.5));
  CHECK(t.time()[1] == doctest::Approx(1611326939.0)); // the same hour in UTC + 1
  CHECK(t.time()[2] == doctest::Approx(1611360000.0));
}

TEST_CASE("campaign: a sensor lags its node; a series of the node is compared with its reading") {
  TempDir dir("campaign");
  // The room steps up by 10 K; the box follows with tau_box = C / G = 500 s, the sensor with 100 s.
  dir.write("d.csv", "time,box\n0,20\n100,20\n");
  Campaign clean(dir, "boundary room T = step(0: 20, 1: 30)\nnode box C = 1000 T0 = 20\n"
                      "conductance g box room G = 2\nsensor probe box tau = 100 offset = 0.5\n"
                      "case c { duration = 3000\n data \"d.csv\" }\n");
  clean.require_clean();
  std::vector<double> times;
  for (int k = 0; k <= 30; ++k)
    times.push_back(100.0 * k);
  const auto r = clean.run("c", times, true);
  REQUIRE(r.temps.front().size() == 3); // room, box, then the sensor's reading
  // Analytic: box = 30 - 10 e^{-t/a}, reading = 30.5 - 10 (a e^{-t/a} - b e^{-t/b}) / (a - b).
  const double a = 500, b = 100;
  for (std::size_t k = 1; k < r.times.size(); ++k) {
    const double t = r.times[k] - 1.0; // the step is at 1 s
    const double box = 30 - 10 * std::exp(-t / a);
    const double reading = 30.5 - 10 * (a * std::exp(-t / a) - b * std::exp(-t / b)) / (a - b);
    CHECK(r.temps[k][1] - 273.15 == doctest::Approx(box).epsilon(1e-5));
    CHECK(r.temps[k][2] - 273.15 == doctest::Approx(reading).epsilon(1e-5));
  }
  const NetworkSpec spec = clean.model->instantiate("c");
  const MeasuredData d = load_measured(spec.settings.data_path, spec);
  REQUIRE(d.series.size() == 1);
  CHECK(d.series[0].sensor >= 0);
  CHECK(d.series[0].node == "box");
}

TEST_CASE("campaign: a key read by another follows the case's setting; a cycle is an error") {
  TempDir dir("campaign");
  Campaign m(dir, std::string(kHeatedBox) +
                      "heater film box P = 10\nheater half box P = 0.5 * film.P\n"
                      "heater copy box P = film.P\n"
                      "case c { duration = 100\n film.P = step(0: 4, 50: 8) }\n"
                      "case d { duration = 100 }\n");
  m.require_clean();
  const NetworkSpec c = m.model->instantiate("c");
  const auto& half = c.elements[2].values.at("P");
  const auto& copy = c.elements[3].values.at("P");
  CHECK(half.at(10) == doctest::Approx(2.0));
  CHECK(half.at(60) == doctest::Approx(4.0));
  CHECK(copy.kind() == Signal::Kind::step); // a lone reference keeps the signal's corners
  CHECK(copy.at(60) == doctest::Approx(8.0));
  CHECK(m.model->instantiate("d").elements[2].values.at("P").at(10) == doctest::Approx(5.0));

  Campaign cycle(dir, std::string(kHeatedBox) + "heater a box P = b.P\nheater b box P = 2 * a.P\n"
                                                "case c { duration = 100 }\n");
  const auto codes = cycle.codes();
  CHECK(std::find(codes.begin(), codes.end(), "cycle") != codes.end());
}

TEST_CASE("campaign: long chains of keys read through one another: bounded, never quadratic") {
  TempDir dir("campaign");
  // Each heater reads the next one's power: a chain resolved by recursion, one level per link.
  // 20,000 links used to overflow the stack; beyond max_reference_depth it is an error at the
  // link where the bound is reached.
  Campaign deep(dir, std::string(kHeatedBox) +
                         "heater h[20001] box P = 1\n"
                         "for i in 1 .. 20000 { heater h[i] box P = h[i + 1].P }\n"
                         "case c { duration = 100 }\n");
  INFO(render_text(deep.diags));
  REQUIRE(deep.diags.error_count() >= 1);
  CHECK(render_text(deep.diags).find("'h[101].P' is read through a chain of more than 100 keys") !=
        std::string::npos);
  // As deep as the bound allows: fine, every heater at the last one's power.
  Campaign bounded(dir, std::string(kHeatedBox) +
                            "heater h[100] box P = 3\n"
                            "for i in 1 .. 99 { heater h[i] box P = h[i + 1].P }\n"
                            "case c { duration = 100 }\n");
  bounded.require_clean();
  CHECK(bounded.model->instantiate("c").elements.back().values.at("P").at(0) ==
        doctest::Approx(3.0));
  // In declaration order the chain needs no recursion: 20,000 links are fine (and take a lookup
  // each: this took seconds when every key scanned every reference).
  Campaign forward(dir, std::string(kHeatedBox) +
                            "heater h[0] box P = 0.5\n"
                            "for i in 1 .. 20000 { heater h[i] box P = h[i - 1].P }\n"
                            "case c { duration = 100 }\n");
  forward.require_clean();
  const NetworkSpec net = forward.model->instantiate("c");
  CHECK(net.elements.back().values.at("P").at(0) == doctest::Approx(0.5));
}

TEST_CASE("campaign: a start temperature calibrated per case is a param of that case") {
  TempDir dir("campaign");
  dir.write("d1.csv", "time,a\n0,30\n600,26\n1200,24\n");
  dir.write("d2.csv", "time,a\n0,30\n600,27\n1200,25\n");
  Campaign m(dir, "boundary room T = 20\nnode a C = 1000\nnode w C = 5000\n"
                  "conductance g1 a w G = 5\nconductance g2 w room G = 2\n"
                  "case one { duration = 1200\n initial = data\n w.T0 = 25 range 10 .. 40\n"
                  " data \"d1.csv\" }\n"
                  "case two { duration = 1200\n initial = data\n w.T0 = 30 range 10 .. 40\n"
                  " data \"d2.csv\" }\n");
  m.require_clean();
  const auto params = m.model->params();
  REQUIRE(params.size() == 2);
  CHECK(params[0].name == "w.T0@one");
  CHECK(params[0].value == doctest::Approx(25 + 273.15));
  CHECK(*params[0].lo == doctest::Approx(10 + 273.15));
  CHECK(params[1].name == "w.T0@two");
  // Each case takes its own; the other case's is not its concern.
  const NetworkSpec one = m.model->instantiate("one", {{"w.T0@one", 300.0}, {"w.T0@two", 290.0}});
  CHECK(*one.nodes[2].T0 == doctest::Approx(300.0));
  const NetworkSpec two = m.model->instantiate("two", {{"w.T0@one", 300.0}, {"w.T0@two", 290.0}});
  CHECK(*two.nodes[2].T0 == doctest::Approx(290.0));
  // Calibration sees them as dimensions of the problem.
  CalibrationProblem problem(*m.model);
  CHECK(problem.dimension() == 2);
}

TEST_CASE("campaign: initial = data starts an unmeasured node at the steady state around it") {
  TempDir dir("campaign");
  dir.write("d.csv", "time,inside\n0,30\n60,29.9\n");
  Campaign m(dir, "boundary outdoors T = 10\nnode inside C = 1e5\nnode wall C = 1e6\n"
                  "conductance gi inside wall G = 3\nconductance go wall outdoors G = 1\n"
                  "case c { duration = 60\n initial = data\n data \"d.csv\" }\n");
  m.require_clean();
  Network net(m.model->instantiate("c"));
  const std::vector<double> T = start_state(net, SolverOptions{});
  // inside held at 30 degC; the wall at (3 * 30 + 1 * 10) / 4 = 25 degC.
  CHECK(T[0] - 273.15 == doctest::Approx(30.0));
  CHECK(T[1] - 273.15 == doctest::Approx(25.0));
}

TEST_CASE("campaign: values computed while a run goes on are checked where they are evaluated") {
  TempDir dir("campaign");
  Campaign m(dir, std::string(kHeatedBox) + "boundary cold T = 20 - time\n"
                                            "conductance gc box cold G = 1\n"
                                            "case c { duration = 1000 }\n");
  m.require_clean(); // valid at t = 0
  Network net(m.model->instantiate("c"));
  SimulationOptions o;
  o.duration = 1000;
  try {
    simulate(net, o);
    FAIL("a boundary below 0 K went unnoticed");
  } catch (const ModelError& e) {
    CHECK(e.diag.code == "invalid-value");
    CHECK(e.diag.message.find("T of boundary 'cold'") != std::string::npos);
    CHECK(e.diag.message.find("above absolute zero") != std::string::npos);
    REQUIRE(e.diag.at);
  }
}
