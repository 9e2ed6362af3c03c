// Unit tests of the mass and input kinds of `thermnet diagnose` (issue 29): a mass inside a link
// (wall_mass), a mass tied to a node (hidden_mass), a share of a heater's power heating another
// node (input_split). Each truth is the room model with the effect written out; its data are the
// truth's simulation plus noise. The diagnosis must name the effect with its size, and the model
// it writes must lint without warnings and fit the data at the noise floor with no finding left
// (a written model is diagnosed again like any other).
#include "app/diagnosis_output.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "kernel/diagnosis/composites.hpp"
#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/diagnosis/report.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

namespace {

using namespace thermnet;

/// A room: the air, a slab, the envelope to the outdoors, a heater on the air; two cases.
/// `envelope` is the link's statement, `extra` the truth's additions.
std::string room(const std::string& envelope, const std::string& extra, bool data) {
  return fmt::format(R"(boundary outdoors T = pwl(0: 5, 20000: 12, 40000: 2)
node air C = 2e5 [J/K] T0 = 18
node slab C = 1.5e6 [J/K] T0 = 18
conductance g_slab air slab G = 40 [W/K]
{}
heater h air P = step(0: 2000 [W], 14400: 0 [W], 28800: 1500 [W])
{}
case one {{ duration = 43200; output = 300{} }}
case two {{ duration = 43200; output = 300; h.P = step(0: 0 [W], 7200: 2500 [W], 21600: 0 [W]){} }}
)",
                     envelope, extra, data ? "; data \"one.csv\"" : "",
                     data ? "; data \"two.csv\"" : "");
}

constexpr const char* kEnvelope = "conductance envelope air outdoors G = 60 [W/K]";

/// Writes the truth's data (air and slab measured, N(0, 0.03 K)) and returns the model's path.
std::string make(const test::TempDir& dir, const std::string& truth, const std::string& model) {
  test::LoadedModel gen(dir.write("truth.tnet", truth), test::Lint::clean);
  std::mt19937_64 rng(29);
  std::normal_distribution<double> noise(0.0, 0.03);
  for (const std::string c : {"one", "two"}) {
    Network net(gen.model->instantiate(c));
    const SimulationResult r = simulate(net);
    std::string csv = "time,air,slab\n";
    for (std::size_t k = 0; k < r.times.size(); ++k)
      csv += fmt::format("{},{:.4f},{:.4f}\n", r.times[k],
                         r.temps[k][static_cast<std::size_t>(net.spec().node_index("air"))] -
                             273.15 + noise(rng),
                         r.temps[k][static_cast<std::size_t>(net.spec().node_index("slab"))] -
                             273.15 + noise(rng));
    dir.write(c + ".csv", csv);
  }
  return dir.write("model.tnet", model);
}

DiagnosisReport run(const std::string& path) {
  test::LoadedModel m(path, test::Lint::clean);
  DiagnosisOptions opt;
  opt.threads = 2;
  opt.top = 2;
  return diagnose(*m.model, opt);
}

/// The first finding that is not a recalibration.
const Finding& structural(const DiagnosisReport& r) {
  for (const auto& f : r.findings)
    if (f.candidate.kind != "parameter") return f;
  FAIL("no structural finding:\n", diagnosis_text(r));
  return r.findings.front();
}

/// Writes the model with the finding applied, requires it to lint without warnings, and
/// diagnoses it again.
DiagnosisReport rediagnose(const test::TempDir& dir, const std::string& path, const Finding& f,
                           std::string& text) {
  test::LoadedModel m(path);
  text = app::extended_model_text(*m.model, f);
  test::LoadedModel e(dir.write("ext.tnet", text), test::Lint::clean);
  INFO(text);
  CHECK(e.diags.warning_count() == 0);
  return run(dir.write("ext.tnet", text));
}

/// `text` with the first `from` replaced by `to` (the test fails when there is none).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

double value(const Finding& f, const std::string& name) {
  return finding_values(f).at(name);
}

} // namespace

TEST_CASE("diagnose masses: a mass inside the envelope splits the link (wall_mass)") {
  // The truth's envelope: 1/3 of its resistance between the air and a 4e6 J/K wall.
  test::TempDir dir;
  const std::string truth =
      room("node wall C = 4e6 [J/K] T0 = 18\nconductance env_a air wall G = 180 [W/K]\n"
           "conductance env_b wall outdoors G = 90 [W/K]",
           "", false);
  const std::string path = make(dir, truth, room(kEnvelope, "", true));
  const DiagnosisReport r = run(path);
  INFO(diagnosis_text(r));
  const Finding& f = structural(r);
  CHECK(f.candidate.kind == "wall_mass");
  CHECK(f.candidate.element == "envelope");
  CHECK(value(f, "C") == doctest::Approx(4e6).epsilon(0.05));
  CHECK(value(f, "f") == doctest::Approx(1.0 / 3.0).epsilon(0.05));
  CHECK(f.retired == std::vector<std::string>{"envelope"});
  std::string text;
  const DiagnosisReport again = rediagnose(dir, path, f, text);
  CHECK(text.find("# conductance envelope air outdoors G = 60 [W/K]") != std::string::npos);
  CHECK(text.find("conductance envelope air diag_wall_envelope G = (60 [W/K]) / "
                  "diag_wall_envelope_f") != std::string::npos);
  CHECK_MESSAGE(again.findings.empty(), diagnosis_text(again));
  CHECK(again.baseline.rmse < 1.3 * again.noise_floor);
}

TEST_CASE("diagnose masses: a mass tied to the air (hidden_mass)") {
  test::TempDir dir;
  const std::string truth =
      room(kEnvelope,
           "node object C = 8e5 [J/K] T0 = 18\nconductance g_obj object air G = 25 [W/K]", false);
  const std::string path = make(dir, truth, room(kEnvelope, "", true));
  const DiagnosisReport r = run(path);
  INFO(diagnosis_text(r));
  const Finding& f = structural(r);
  CHECK(f.candidate.kind == "hidden_mass");
  CHECK(f.candidate.nodes == std::vector<std::string>{"air"});
  CHECK(value(f, "C") == doctest::Approx(8e5).epsilon(0.05));
  CHECK(value(f, "tau") == doctest::Approx(8e5 / 25).epsilon(0.05));
  std::string text;
  const DiagnosisReport again = rediagnose(dir, path, f, text);
  CHECK(text.find("node diag_hidden_air C = diag_hidden_air_C T0 = 18") != std::string::npos);
  CHECK_MESSAGE(again.findings.empty(), diagnosis_text(again));
}

TEST_CASE("diagnose masses: a share of the heater's power heats the slab (input_split)") {
  test::TempDir dir;
  const std::string truth = room(kEnvelope,
                                 "heater h_slab slab P = step(0: 800 [W], 14400: 0 [W], 28800: 600 "
                                 "[W])",
                                 false);
  // (the truth's heater h keeps 60 % of the modelled power, h_slab puts the rest into the slab)
  std::string t = replaced(truth, "P = step(0: 2000 [W], 14400: 0 [W], 28800: 1500 [W])",
                           "P = step(0: 1200 [W], 14400: 0 [W], 28800: 900 [W])");
  t = replaced(t, "h.P = step(0: 0 [W], 7200: 2500 [W], 21600: 0 [W])",
               "h.P = step(0: 0 [W], 7200: 1500 [W], 21600: 0 [W]); h_slab.P = step(0: 0 [W], "
               "7200: 1000 [W], 21600: 0 [W])");
  const std::string path = make(dir, t, room(kEnvelope, "", true));
  const DiagnosisReport r = run(path);
  INFO(diagnosis_text(r));
  const Finding& f = structural(r);
  CHECK(f.candidate.kind == "input_split");
  CHECK(f.candidate.element == "h");
  CHECK(f.candidate.nodes == std::vector<std::string>{"air", "slab"});
  CHECK(value(f, "share") == doctest::Approx(0.4).epsilon(0.05));
  std::string text;
  const DiagnosisReport again = rediagnose(dir, path, f, text);
  CHECK_MESSAGE(again.findings.empty(), diagnosis_text(again));
}

TEST_CASE("a share into a mass on its upper bound is the heater's own mass, also on top of "
          "findings") {
  // The forward selection judges a step's candidate by its refit together with the findings
  // (a Compose of them and it): there too a split with all the power it may move is degenerate.
  const std::unique_ptr<Hypothesis> split =
      HypothesisRegistry::global().find("input_split")->create();
  Candidate onto; // a share onto another node (the finding applied first)
  onto.kind = "input_split";
  onto.nodes = {"air", "slab"};
  onto.names = {"share"};
  onto.start = {0.3};
  onto.lo = {0.005};
  onto.hi = {1.0};
  Candidate mass = onto; // a share into a mass of its own (the step's candidate)
  mass.nodes = {"air"};
  mass.names = {"share", "C", "tau"};
  mass.start = {0.5, 1e4, 900.0};
  mass.lo = {0.005, 10.0, 600.0};
  mass.hi = {0.95, 1e7, 1e6};
  CHECK(split->degenerate(mass, {0.95, 1e4, 900.0}));
  CHECK_FALSE(split->degenerate(mass, {0.5, 1e4, 900.0}));
  const detail::Compose both({{split.get(), onto, {1.0}}, {split.get(), mass, {0.5, 1e4, 900.0}}});
  CHECK(both.degenerate(both.candidate(), {0.3, 0.95, 1e4, 900.0}));
  CHECK_FALSE(both.degenerate(both.candidate(), {0.3, 0.5, 1e4, 900.0}));
  // (the finding below it on its own bound says nothing of the step's candidate)
  CHECK_FALSE(both.degenerate(both.candidate(), {1.0, 0.5, 1e4, 900.0}));
}
