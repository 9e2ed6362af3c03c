// Unit tests of `thermnet diagnose`: hidden effects. Each test builds a truth model, makes
// "measured" data with thermnet's simulator plus Gaussian noise, removes the effect from the model
// and requires the diagnosis to name it (kind, nodes, mechanism where identifiable) with a fitted
// size close to the truth. Clean data must give no finding. Three networks: a 4-node chain with a
// step heater, an 8-node instrument with radiation, a pwl boundary and two cases, and a 20-node
// plate for the speed check.

#include "app/diagnosis_output.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/diagnosis/engine.hpp"
#include "kernel/diagnosis/report.hpp"
#include "kernel/diagnosis/statistics.hpp"

#include <boost/math/distributions/chi_squared.hpp>
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <unistd.h>
#include <vector>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

using thermnet::test::TempDir;

namespace {

namespace fs = std::filesystem;
using namespace thermnet;

constexpr double kZeroCelsius = 273.15;

/// A model loaded and linted clean.
struct Loaded : test::LoadedModel {
  explicit Loaded(const std::string& path) : LoadedModel(path, test::Lint::clean) {}
};

/// Measurement-side effects applied when making data.
struct Sensor {
  std::string node;
  double offset = 0.0; ///< K
  double tau = 0.0;    ///< s
};

/// One test setup: a model template with `{EXTRA}` (where the hidden statements go) and
/// `{DATA:case}` placeholders, the cases, the measured nodes.
struct Setup {
  std::string text;
  std::vector<std::string> cases;
  std::vector<std::string> measured;
  double sigma = 0.05;
};

std::string fill(std::string text, const std::string& extra, bool with_data,
                 const std::vector<std::string>& cases) {
  auto replace = [&](const std::string& key, const std::string& by) {
    for (auto p = text.find(key); p != std::string::npos; p = text.find(key))
      text.replace(p, key.size(), by);
  };
  replace("{EXTRA}", extra);
  for (const auto& c : cases)
    replace("{DATA:" + c + "}", with_data ? fmt::format("; data \"{}.csv\"", c) : "");
  return text;
}

/// Writes truth data (truth = template + hidden), then the model without the effect; returns the
/// diagnosed model's path.
std::string make_case(const TempDir& dir, const Setup& s, const std::string& hidden,
                      const std::string& truth_base, const std::vector<Sensor>& sensors = {},
                      unsigned seed = 7) {
  const std::string truth = dir.write("truth.tnet", fill(truth_base, hidden, false, s.cases));
  Loaded gen(truth);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, s.sigma);
  for (const auto& c : s.cases) {
    Network net(gen.model->instantiate(c));
    SimulationResult r = simulate(net);
    std::string csv = "time";
    for (const auto& n : s.measured)
      csv += "," + n;
    csv += "\n";
    std::vector<std::vector<double>> cols;
    for (const auto& n : s.measured) {
      const auto i = static_cast<std::size_t>(net.spec().node_index(n));
      std::vector<double> v;
      for (const auto& row : r.temps)
        v.push_back(row[i]);
      for (const auto& sen : sensors)
        if (sen.node == n) {
          if (sen.tau > 0) {
            std::vector<double> y(v.size());
            y[0] = v[0];
            for (std::size_t k = 1; k < v.size(); ++k) {
              const double h = r.times[k] - r.times[k - 1], E = std::exp(-h / sen.tau);
              const double a = (v[k] - v[k - 1]) / h;
              y[k] = v[k] - a * sen.tau + (y[k - 1] - v[k - 1] + a * sen.tau) * E;
            }
            v = y;
          }
          for (double& x : v)
            x += sen.offset;
        }
      cols.push_back(v);
    }
    for (std::size_t k = 0; k < r.times.size(); ++k) {
      csv += fmt::format("{}", r.times[k]);
      for (auto& col : cols)
        csv += fmt::format(",{:.5f}", col[k] - kZeroCelsius + noise(rng));
      csv += "\n";
    }
    dir.write(c + ".csv", csv);
  }
  return dir.write("model.tnet", fill(s.text, "", true, s.cases));
}

DiagnosisReport run(const std::string& path, DiagnosisReport* out = nullptr) {
  Loaded m(path);
  DiagnosisReport r = diagnose(*m.model);
  if (out) *out = r;
  return r;
}

/// The report plus the refitted candidates that were not significant, for failure messages.
std::string explain(const DiagnosisReport& r) {
  std::string s = diagnosis_text(r) + "rejected:\n";
  for (const auto& f : r.rejected)
    s += fmt::format("  {} [{}] {} rmse {:.4g} -> {:.4g} val {:.4g} -> {:.4g} dBIC {:.4g}\n",
                     f.candidate.kind, fmt::join(f.candidate.nodes, ","), f.candidate.mechanism,
                     f.rmse_before, f.rmse_after, f.validation_rmse_before, f.validation_rmse_after,
                     f.delta_bic);
  return s;
}

const Finding& top(const DiagnosisReport& r) {
  REQUIRE_MESSAGE(!r.findings.empty(), explain(r));
  return r.findings.front();
}

double value(const Finding& f, const std::string& name) {
  auto v = finding_values(f);
  REQUIRE(v.count(name));
  return v.at(name);
}

bool same_pair(const Finding& f, const std::string& a, const std::string& b) {
  const auto& n = f.candidate.nodes;
  return n.size() == 2 && ((n[0] == a && n[1] == b) || (n[0] == b && n[1] == a));
}

// ------------------------------------------------------------------ network A: 4-node chain

const char* const kChain = R"(model chain
boundary amb T = 20
node n1 C = 800 [J/K] T0 = 20
node n2 C = {C2} [J/K] T0 = 20
node n3 C = 500 [J/K] T0 = 20
node n4 C = 400 [J/K] T0 = 20
conductance g12 n1 n2 G = 2 [W/K]
conductance g23 n2 n3 G = 1.5 [W/K]
conductance g34 n3 n4 G = 1 [W/K]
conductance g4a n4 amb G = 0.8 [W/K]
heater film n1 P = step(0: {P} [W], 3600: 0 [W])
{EXTRA}
case run { duration = 7200; output = 60 {DATA:run} }
)";

std::string chain(double C2 = 600, double P = 20) {
  std::string t = kChain;
  t.replace(t.find("{C2}"), 4, netlist_number(C2));
  t.replace(t.find("{P}"), 3, netlist_number(P));
  return t;
}

/// The chain with g12 and g34 sharing one ranged param Gc declared at `value` W/K.
std::string chain_with_param(double value) {
  std::string t = chain();
  t.replace(
      t.find("conductance g12 n1 n2 G = 2 [W/K]"), 33,
      fmt::format("param Gc = {} [W/K] range 0.2 .. 10\nconductance g12 n1 n2 G = Gc", value));
  t.replace(t.find("conductance g34 n3 n4 G = 1 [W/K]"), 33, "conductance g34 n3 n4 G = Gc");
  return t;
}

Setup chain_setup(double C2 = 600, double P = 20) {
  return {chain(C2, P), {"run"}, {"n1", "n2", "n3", "n4"}, 0.05};
}

} // namespace

TEST_CASE("diagnosis helpers: noise estimate and smoothing") {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::vector<double> t, v;
  for (int k = 0; k < 400; ++k) {
    t.push_back(10.0 * k);
    v.push_back(20.0 + 5.0 * std::sin(k / 60.0) + noise(rng));
  }
  CHECK(estimate_noise(v) == doctest::Approx(0.2).epsilon(0.15));
  std::vector<double> sm, sl;
  smooth_series(t, v, 6, sm, sl);
  CHECK(sl[200] == doctest::Approx(5.0 * std::cos(200 / 60.0) / 600.0).epsilon(0.2));
}

TEST_CASE("diagnose chain: clean data gives no finding") {
  TempDir dir;
  const Setup s = chain_setup();
  const auto path = make_case(dir, s, "", s.text);
  const auto r = run(path);
  CHECK_MESSAGE(r.findings.empty(), diagnosis_text(r));
  CHECK(r.noise_floor == doctest::Approx(0.05).epsilon(0.3));
  const auto j = diagnosis_json(r);
  CHECK(j["findings"].is_array());
  CHECK(j["findings"].empty());
  CHECK(j["baseline"]["nodes"]["n2"].contains("trend_mismatch_s"));
}

TEST_CASE("diagnose chain: hidden linear link n1-n4") {
  TempDir dir;
  const Setup s = chain_setup();
  const auto path = make_case(dir, s, "conductance hid n1 n4 G = 0.5 [W/K]", s.text);
  const auto r = run(path);
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "missing_link");
  CHECK(same_pair(f, "n1", "n4"));
  CHECK(value(f, "G") == doctest::Approx(0.5).epsilon(0.1));
  CHECK(f.rmse_after < 0.1);
  // JSON shape per the spec.
  const auto j = diagnosis_json(r);
  const auto& jf = j["findings"][0];
  CHECK(jf["rank"] == 1);
  CHECK(jf["kind"] == "missing_link");
  CHECK(jf["nodes"].size() == 2);
  CHECK(jf["values"].contains("G"));
  for (const char* key :
       {"statement", "evidence", "rmse_after", "r2_after", "validation_rmse_after", "mechanism"})
    CHECK_MESSAGE(jf.contains(key), key);
  for (const char* key : {"model", "noise_floor", "baseline"})
    CHECK(j.contains(key));
  for (const char* key : {"rmse", "bias", "max_error", "max_error_time", "trend_mismatch_s"})
    CHECK(j["baseline"]["nodes"]["n1"].contains(key));
  // --write: the extended model lints clean and fits the data.
  Loaded m(path);
  const std::string ext = dir.write("ext.tnet", app::extended_model_text(*m.model, f));
  CHECK(ext.size() > 0);
  Loaded e(ext);
  const auto r2 = diagnose(*e.model);
  CHECK(r2.baseline.rmse < 0.1);
  CHECK_MESSAGE(r2.findings.empty(), diagnosis_text(r2));
}

TEST_CASE("diagnose chain: hidden source on n3") {
  TempDir dir;
  const Setup s = chain_setup();
  const auto r = run(make_case(dir, s, "heater hidsrc n3 P = 2 [W]", s.text));
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "missing_source");
  CHECK(f.candidate.nodes == std::vector<std::string>{"n3"});
  CHECK(value(f, "P") == doctest::Approx(2.0).epsilon(0.1));
}

TEST_CASE("diagnose chain: capacity of n2 is wrong") {
  TempDir dir;
  const Setup s = chain_setup(600);
  const auto path = make_case(dir, s, "", chain(1500));
  const auto r = run(path);
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "capacity_error");
  CHECK(f.candidate.nodes == std::vector<std::string>{"n2"});
  CHECK(value(f, "factor") == doctest::Approx(2.5).epsilon(0.1));
  Loaded m(path);
  Loaded e(dir.write("ext.tnet", app::extended_model_text(*m.model, f)));
  CHECK(diagnose(*e.model).baseline.rmse < 0.1);
}

TEST_CASE("diagnose chain: heater delivers more than modelled") {
  TempDir dir;
  const Setup s = chain_setup(600, 15);
  const auto path = make_case(dir, s, "", chain(600, 20));
  const auto r = run(path);
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "heater_gain");
  CHECK(f.candidate.element == "film");
  CHECK(value(f, "factor") == doctest::Approx(20.0 / 15.0).epsilon(0.05));
  Loaded m(path);
  Loaded e(dir.write("ext.tnet", app::extended_model_text(*m.model, f)));
  CHECK(diagnose(*e.model).baseline.rmse < 0.1);
}

TEST_CASE("diagnose chain: a heater on an unmeasured node delivers more than modelled") {
  // n1 (the heater's node) has no sensor, and no other heater's candidate sits near it: its
  // heater_gain has no screen score and is refitted because its kind has few such candidates.
  TempDir dir;
  Setup s = chain_setup(600, 15);
  s.measured = {"n2", "n3", "n4"};
  const auto r = run(make_case(dir, s, "", chain(600, 20)));
  const Finding& f = top(r);
  bool named = f.candidate.kind == "heater_gain" && f.candidate.element == "film";
  for (const auto& rival : f.rivals)
    named = named || (rival.candidate.kind == "heater_gain" && rival.candidate.element == "film");
  CHECK_MESSAGE(named, explain(r));
  if (f.candidate.kind == "heater_gain")
    CHECK(value(f, "factor") == doctest::Approx(20.0 / 15.0).epsilon(0.05));
}

TEST_CASE("diagnose chain: sensor offset on n2") {
  TempDir dir;
  const Setup s = chain_setup();
  const auto r = run(make_case(dir, s, "", s.text, {{"n2", 0.8, 0.0}}));
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "sensor_offset");
  CHECK(f.candidate.nodes == std::vector<std::string>{"n2"});
  CHECK(value(f, "offset") == doctest::Approx(0.8).epsilon(0.05));
}

TEST_CASE("diagnose chain: sensor lag on n1") {
  TempDir dir;
  const Setup s = chain_setup();
  const auto r = run(make_case(dir, s, "", s.text, {{"n1", 0.0, 150.0}}));
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "sensor_lag");
  CHECK(f.candidate.nodes == std::vector<std::string>{"n1"});
  CHECK(value(f, "tau") == doctest::Approx(150.0).epsilon(0.1));
}

TEST_CASE("diagnose chain: a radiative link over a narrow span is not told apart") {
  TempDir dir;
  Setup s = chain_setup(600, 4);
  s.sigma = 0.1;
  const auto r = run(make_case(dir, s, "radiation hid n1 n4 GR = 0.08 [m^2]", chain(600, 4)));
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "missing_link");
  CHECK(same_pair(f, "n1", "n4"));
  CHECK_MESSAGE(!f.mechanism_identified, diagnosis_text(r));
  CHECK(f.mechanism_note.find("fit equally") != std::string::npos);
}

namespace {

// --------------------------- network A2: 2 nodes, 2 cases that each override the heater's power

const char* const kTwoCases = R"(model twocases
boundary amb T = 20
node a C = 800 [J/K] T0 = 20
node b C = {CB} [J/K] T0 = 20
conductance gab a b G = 2 [W/K]
conductance gba b amb G = 0.8 [W/K]
heater h a P = {P} [W]
{EXTRA}
case run1 { duration = 6000; output = 60; h.P = step(0: {P} [W], 2000: 0 [W]) {DATA:run1} }
case run2 { duration = 6000; output = 60; h.P = {P2} [W]; b.C = {CB2} [J/K] {DATA:run2} }
)";

/// The two-case model: heater power P (run1: P until 2000 s; run2: P2 throughout) and the
/// capacity of b (CB declared, CB2 in run2).
std::string two_cases(double P, double P2, double CB, double CB2) {
  std::string t = kTwoCases;
  for (const auto& [key, v] :
       {std::pair{"{P}", P}, std::pair{"{P2}", P2}, std::pair{"{CB}", CB}, std::pair{"{CB2}", CB2}})
    for (auto p = t.find(key); p != std::string::npos; p = t.find(key))
      t.replace(p, std::string(key).size(), netlist_number(v));
  return t;
}

/// Writes the model at `path` extended by `f` (--write), requires it to lint clean, warnings
/// included, and diagnoses it again.
DiagnosisReport rediagnose(const TempDir& dir, const std::string& path, const Finding& f,
                           std::string& text) {
  Loaded m(path);
  text = app::extended_model_text(*m.model, f);
  Loaded e(dir.write("ext.tnet", text));
  CHECK(e.diags.warning_count() == 0);
  return diagnose(*e.model);
}

/// Every node of every case fits at the noise floor.
void check_every_case_at_floor(const DiagnosisReport& r) {
  REQUIRE(r.baseline.cases.size() == 2);
  for (const auto& [name, nodes] : r.baseline.cases)
    for (const auto& [node, m] : nodes)
      CHECK_MESSAGE(m.rmse < 1.5 * r.noise_floor, name, " ", node, " RMSE ", m.rmse);
  CHECK_MESSAGE(r.findings.empty(), diagnosis_text(r));
}

} // namespace

TEST_CASE("diagnose two cases: a heater gain follows every case's own power") {
  TempDir dir;
  const Setup s{two_cases(15, 8, 500, 300), {"run1", "run2"}, {"a", "b"}, 0.02};
  const auto path = make_case(dir, s, "", two_cases(0.7 * 15, 0.7 * 8, 500, 300));
  const auto r = run(path);
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "heater_gain");
  CHECK(value(f, "factor") == doctest::Approx(0.7).epsilon(0.02));
  CHECK(f.rmse_after < 1.5 * r.noise_floor);
  // One extra heater reads the heater's power by name, so every case's own power is corrected
  // without a line in its block.
  CHECK(f.statement.find("heater diag_gain_h a P = -0.3") == 0);
  CHECK(f.statement.find("* h.P") != std::string::npos);
  CHECK(f.case_statements.empty());
  std::string text;
  check_every_case_at_floor(rediagnose(dir, path, f, text));
}

TEST_CASE("diagnose two cases: a capacity error is written for every case's own capacity") {
  TempDir dir;
  const Setup s{two_cases(15, 8, 500, 300), {"run1", "run2"}, {"a", "b"}, 0.02};
  const auto path = make_case(dir, s, "", two_cases(15, 8, 1250, 750));
  const auto r = run(path);
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "capacity_error");
  CHECK(f.candidate.nodes == std::vector<std::string>{"b"});
  CHECK(value(f, "factor") == doctest::Approx(2.5).epsilon(0.05));
  REQUIRE(f.case_statements.size() == 2);
  CHECK(f.case_statements.at("run1").find("b.C = 12") == 0);
  CHECK(f.case_statements.at("run2").find("b.C = 7") == 0);
  std::string text;
  check_every_case_at_floor(rediagnose(dir, path, f, text));
}

namespace {

// ------------------------------------------- network B: 8-node instrument, radiation, 2 cases

const char* const kInstrument = R"(model instrument
boundary space T = pwl(0: 10, 3 [h]: -30)
node base C = 3000 [J/K] T0 = 15
node plate C = 900 [J/K] T0 = 15
node lamp C = 300 [J/K] T0 = 15
node lens C = 250 [J/K] T0 = 15
node barrel C = 500 [J/K] T0 = 15
node window C = 200 [J/K] T0 = 15
node cover C = 1200 [J/K] T0 = 15
node elec C = 600 [J/K] T0 = 15
conductance g1 base plate G = 3 [W/K]
conductance g2 plate barrel G = 1.2 [W/K]
conductance g3 barrel lens G = 0.8 [W/K]
conductance g4 barrel window G = 0.5 [W/K]
conductance g5 plate elec G = 2 [W/K]
conductance g6 base cover G = 1.5 [W/K]
conductance g7 lamp plate G = 0.15 [W/K]
radiation r1 cover space GR = 0.05 [m^2]
radiation r2 window space GR = 0.01 [m^2]
conductance g8 base space G = 0.6 [W/K]
heater hl lamp P = step(0: 60 [W], 5400: 0 [W])
heater he elec P = 10 [W]
{EXTRA}
case hot { duration = 3 [h]; output = 60 {DATA:hot} }
case mild { duration = 3 [h]; output = 60; hl.P = step(0: 30 [W], 3600: 0 [W]) {DATA:mild} }
)";

Setup instrument_setup() {
  return {kInstrument,
          {"hot", "mild"},
          {"base", "plate", "lamp", "lens", "barrel", "window", "cover", "elec"},
          0.05};
}

} // namespace

TEST_CASE("diagnose instrument: clean data gives no finding") {
  TempDir dir;
  const Setup s = instrument_setup();
  const auto r = run(make_case(dir, s, "", s.text));
  CHECK_MESSAGE(r.findings.empty(), diagnosis_text(r));
}

TEST_CASE("diagnose instrument: radiative lamp-cover link over a wide span is radiation") {
  TempDir dir;
  const Setup s = instrument_setup();
  const auto r = run(make_case(dir, s, "radiation hid lamp cover GR = 0.004 [m^2]", s.text));
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "missing_link");
  CHECK(same_pair(f, "lamp", "cover"));
  CHECK_MESSAGE(f.candidate.mechanism == "radiation", diagnosis_text(r));
  CHECK(f.mechanism_identified);
  CHECK(value(f, "GR") == doctest::Approx(0.004).epsilon(0.1));
}

TEST_CASE("diagnose instrument: hidden sink in lens and offset on window") {
  TempDir dir;
  const Setup s = instrument_setup();
  {
    const auto r = run(make_case(dir, s, "heater hid lens P = -3 [W]", s.text));
    const Finding& f = top(r);
    CHECK(f.candidate.kind == "missing_source");
    CHECK(f.candidate.nodes == std::vector<std::string>{"lens"});
    CHECK(value(f, "P") == doctest::Approx(-3.0).epsilon(0.1));
  }
  {
    const auto r = run(make_case(dir, s, "", s.text, {{"window", -0.6, 0.0}}));
    const Finding& f = top(r);
    CHECK(f.candidate.kind == "sensor_offset");
    CHECK(f.candidate.nodes == std::vector<std::string>{"window"});
    CHECK(value(f, "offset") == doctest::Approx(-0.6).epsilon(0.05));
  }
}

TEST_CASE("diagnose chain: a shared ranged param is recalibrated") {
  TempDir dir;
  Setup s = chain_setup();
  s.text = chain_with_param(1.0);
  const auto path = make_case(dir, s, "", chain_with_param(2.0));
  const auto r = run(path);
  const Finding& f = top(r);
  CHECK_MESSAGE(f.candidate.kind == "parameter", explain(r));
  CHECK(value(f, "Gc") == doctest::Approx(2.0).epsilon(0.05));
  CHECK(diagnosis_json(r)["findings"][0]["params"].contains("Gc"));
  Loaded m(path);
  Loaded e(dir.write("ext.tnet", app::extended_model_text(*m.model, f)));
  CHECK(diagnose(*e.model).baseline.rmse < 0.1);
}

TEST_CASE("diagnose chain: hidden link n1-n4 while a ranged param is also wrong (joint refit)") {
  // The model's shared conductance Gc is declared at half its true value AND the truth has a hidden
  // link n1-n4. Refitting the link's G alone (at the wrong Gc) cannot reach the noise, and the
  // recalibration alone cannot explain the link: the joint refit must name the link, with both G
  // and Gc close to the truth.
  TempDir dir;
  Setup s = chain_setup();
  s.text = chain_with_param(1.0);
  const auto path = make_case(dir, s, "conductance hid n1 n4 G = 0.5 [W/K]", chain_with_param(2.0));
  const auto r = run(path);
  const Finding& f = top(r);
  CHECK_MESSAGE(f.candidate.kind == "missing_link", explain(r));
  CHECK_MESSAGE(same_pair(f, "n1", "n4"), explain(r));
  CHECK(value(f, "G") == doctest::Approx(0.5).epsilon(0.1));
  CHECK(value(f, "Gc") == doctest::Approx(2.0).epsilon(0.05));
  CHECK(f.rmse_after < 0.1);
  // The recalibration alone is not the best explanation.
  for (const auto& g : r.findings)
    if (g.candidate.kind == "parameter") CHECK(g.rank > f.rank);
  // The recalibration is significant, so the model-side shortlist is refitted jointly only: the
  // refits at the declared params are the measurement-side candidates' and the recalibration's.
  Loaded m(path);
  const detail::Engine engine(*m.model, DiagnosisOptions{});
  std::size_t not_model_side = 0, model_side = 0;
  for (const auto& name : HypothesisRegistry::global().names()) {
    const auto h = HypothesisRegistry::global().find(name)->create();
    for (const auto& c : h->propose(engine.evidence()))
      ++(c.measurement_side || h->recalibrates() ? not_model_side : model_side);
  }
  REQUIRE(model_side > 0);
  REQUIRE(!r.batches.empty());
  CHECK(r.batches.front().base_findings == 0);
  CHECK_FALSE(r.batches.front().joint);
  CHECK(r.batches.front().refits == not_model_side);
}

namespace {

/// A 20-node plate (4 x 5 grid), two boundaries, two cases with different heater schedules.
std::string plate_model() {
  std::string t = "model plate\nboundary amb T = pwl(0: 20, 2 [h]: 5)\nboundary sink T = 10\n";
  for (int i = 0; i < 20; ++i)
    t += fmt::format("node p{} C = {} [J/K] T0 = 15\n", i, 300 + 37 * (i % 7));
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 5; ++c) {
      const int i = r * 5 + c;
      if (c < 4)
        t += fmt::format("conductance gx{} p{} p{} G = {} [W/K]\n", i, i, i + 1, 1.0 + 0.1 * r);
      if (r < 3) t += fmt::format("conductance gy{} p{} p{} G = 0.8 [W/K]\n", i, i, i + 5);
      if (r == 0) t += fmt::format("conductance ga{} p{} amb G = 0.3 [W/K]\n", i, i);
    }
  t += "conductance gs p19 sink G = 1 [W/K]\n";
  t += "heater h1 p2 P = step(0: 25 [W], 3000: 0 [W])\nheater h2 p16 P = 8 [W]\n{EXTRA}\n";
  t += "case a { duration = 2 [h]; output = 60 {DATA:a} }\n";
  t += "case b { duration = 2 [h]; output = 60; h1.P = pwl(0: 0 [W], 3600: 30 [W], 7200: 0 [W]) "
       "{DATA:b} }\n";
  return t;
}

} // namespace

TEST_CASE("diagnose plate: 20 nodes, 2 cases, hidden link to a boundary") {
  TempDir dir;
  Setup s{plate_model(), {"a", "b"}, {}, 0.05};
  for (int i = 0; i < 20; ++i)
    s.measured.push_back(fmt::format("p{}", i));
  const auto path = make_case(dir, s, "conductance hid p7 sink G = 0.4 [W/K]", s.text);
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = run(path);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  MESSAGE(fmt::format("20-node, 2-case diagnosis: {:.2f} s, {} screened, {} refitted\n{}", wall,
                      r.screened, r.refitted, explain(r)));
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "missing_link");
  CHECK_MESSAGE(same_pair(f, "p7", "sink"), explain(r));
  CHECK(value(f, "G") == doctest::Approx(0.4).epsilon(0.1));
  // The timing accounts for every refit, and the refits simulated the cases.
  std::size_t refits = 0, simulations = 0;
  for (const RefitBatch& b : r.batches)
    refits += b.refits, simulations += b.simulations;
  CHECK(refits == r.refitted);
  CHECK(simulations > r.refitted);
  // The plot renders before/after curves.
  const std::string svg = app::diagnosis_svg(r, "plate");
  CHECK(svg.find("<svg") != std::string::npos);
  CHECK(svg.find("after") != std::string::npos);
}

TEST_CASE("diagnosis plot: one distinct colour per node of a panel, titled with the model's name") {
  DiagnosisReport r;
  r.model = "/some/where/on/this/machine/camera.tnet";
  DiagnosisReport::Curves cv;
  cv.case_name = "c1";
  cv.times = {0.0, 60.0, 120.0};
  // Nine nodes with errors in rank order n0 (worst) ... n8: the plot shows the 8 worst.
  for (int i = 0; i < 9; ++i) {
    const std::string name = fmt::format("n{}", i);
    r.baseline.nodes[name].rmse = 10.0 - i;
    cv.measured[name] = {280.0 + i, 281.0 + i, 282.0 + i};
    cv.before[name] = {280.0 + i, 280.5 + i, 281.0 + i};
  }
  r.curves = {cv, cv};
  for (std::size_t worst : {3, 8, 12}) {
    CAPTURE(worst);
    const std::string svg = app::diagnosis_svg(r, "aerial_camera", worst);
    CHECK(svg.find("<title>aerial_camera — no finding</title>") != std::string::npos);
    CHECK(svg.find("/some/where") == std::string::npos);
    // The legend: each entry's swatch (stroke colour) is followed by its label.
    const std::regex entry(
        R"re(stroke="(#[0-9A-Fa-f]{6})"[^<]*/>\s*<text[^>]*>(n[0-9]) before</text>)re");
    std::vector<std::pair<std::string, std::string>> seen; // (node, colour) in document order
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), entry);
         it != std::sregex_iterator(); ++it)
      seen.emplace_back((*it)[2], (*it)[1]);
    const std::size_t shown = std::min<std::size_t>(worst, 8);
    REQUIRE(seen.size() == 2 * shown); // two panels
    for (std::size_t panel = 0; panel < 2; ++panel) {
      std::set<std::string> colours;
      for (std::size_t k = 0; k < shown; ++k) {
        const auto& [node, colour] = seen[panel * shown + k];
        CHECK(node == fmt::format("n{}", k));
        colours.insert(colour);
      }
      CHECK(colours.size() == shown);
    }
  }
}

TEST_CASE("diagnose plate: the gain is validated by leaving each case out") {
  TempDir dir;
  Setup s{plate_model(), {"a", "b"}, {}, 0.05};
  for (int i = 0; i < 20; ++i)
    s.measured.push_back(fmt::format("p{}", i));
  const auto r = run(make_case(dir, s, "heater hid p12 P = -4 [W]", s.text));
  CHECK(r.validation == "leave_one_case_out");
  CHECK(r.folds == 2);
  const Finding& f = top(r);
  CHECK_MESSAGE(f.candidate.kind == "missing_source", explain(r));
  CHECK(f.candidate.nodes == std::vector<std::string>{"p12"});
  CHECK(value(f, "P") == doctest::Approx(-4.0).epsilon(0.1));
  // Each case predicted by the source fitted on the other: close to the noise.
  CHECK(f.validation_rmse_after < 2.0 * r.noise_floor);
  CHECK(f.validation_rmse_before > 5.0 * f.validation_rmse_after);
  const auto j = diagnosis_json(r);
  CHECK(j["validation"]["method"] == "leave_one_case_out");
  CHECK(j["findings"][0]["validation_rmse_after"].get<double>() < 2.0 * r.noise_floor);
  // A proxy of the source (e.g. a link from p12 to a boundary) is not a second finding.
  for (std::size_t i = 1; i < r.findings.size(); ++i)
    CHECK_MESSAGE(std::find(r.findings[i].candidate.nodes.begin(),
                            r.findings[i].candidate.nodes.end(),
                            "p12") == r.findings[i].candidate.nodes.end(),
                  explain(r));
}

TEST_CASE("diagnose chain: two independent causes are found one after the other") {
  // A hidden link n1-n4 and a sensor offset on n2: the best finding is applied and the second is
  // found given it; proxies of the first (a source on n4, a capacity...) are not findings.
  TempDir dir;
  const Setup s = chain_setup();
  const auto r =
      run(make_case(dir, s, "conductance hid n1 n4 G = 0.5 [W/K]", s.text, {{"n2", 0.6, 0.0}}));
  REQUIRE_MESSAGE(r.findings.size() == 2, explain(r));
  const Finding* link = nullptr;
  const Finding* offset = nullptr;
  for (const auto& f : r.findings) {
    if (f.candidate.kind == "missing_link" && same_pair(f, "n1", "n4")) link = &f;
    if (f.candidate.kind == "sensor_offset" && f.candidate.nodes[0] == "n2") offset = &f;
  }
  REQUIRE_MESSAGE(link, explain(r));
  REQUIRE_MESSAGE(offset, explain(r));
  CHECK(value(*link, "G") == doctest::Approx(0.5).epsilon(0.1));
  CHECK(value(*offset, "offset") == doctest::Approx(0.6).epsilon(0.1));
  CHECK(r.findings[1].given == 1);
  CHECK(r.findings[1].rmse_before == doctest::Approx(r.findings[0].rmse_after));
  CHECK(r.findings[1].rmse_after < 0.06);
  CHECK(r.validation == "held_back_time");
  // One case: three equal stretches of it, each held back once.
  CHECK(r.folds == 3);
  CHECK(diagnosis_text(r).find("each of 3 equal stretches of the case") != std::string::npos);
}

TEST_CASE("diagnose chain: an error confined to a few samples is not at the noise floor") {
  // A 0.25 W burst on n3 for 10 minutes of the 2 h run: about 0.1 K on n3 over a dozen samples.
  // The whole fit and every node's RMSE stay within the old floor limits (1.25 and 1.6 times the
  // noise); only the local test sees it.
  TempDir dir;
  const Setup s = chain_setup();
  const auto path =
      make_case(dir, s, "heater burst n3 P = step(0: 0 [W], 4800: 0.25 [W], 5400: 0 [W])", s.text);
  const auto r = run(path);
  const double nf = r.noise_floor;
  double worst = 0.0;
  for (const auto& [name, m] : r.baseline.nodes)
    worst = std::max(worst, m.rmse);
  REQUIRE(r.baseline.rmse <= 1.25 * nf);
  REQUIRE(worst <= 1.6 * nf);
  CHECK(r.baseline.nodes.at("n3").window_rmse > 1.8 * nf);
  CHECK_MESSAGE(!r.at_noise_floor, diagnosis_text(r));
  const auto j = diagnosis_json(r);
  CHECK(j["baseline"]["nodes"]["n3"]["window_rmse"].get<double>() ==
        doctest::Approx(r.baseline.nodes.at("n3").window_rmse));
  // Noise alone stays at the floor, with its largest 10-sample window near the noise.
  TempDir clean_dir;
  const auto clean = run(make_case(clean_dir, s, "", s.text));
  CHECK(clean.at_noise_floor);
  for (const auto& [name, m] : clean.baseline.nodes)
    CHECK(m.window_rmse < 1.8 * clean.noise_floor);
}

TEST_CASE("diagnose chain: noise alone leaves the floor test in at most 1 % of diagnoses") {
  // The floor test's local limit is a Bonferroni bound at 1 % over the 10-sample spans it looks
  // at, and they slide by one sample: about one per measured point. Counting only the disjoint
  // spans (a tenth as many, the rule before 2026-11-30) let 12 of these 400 noise-only data sets
  // fail it (3 %), each then searched for a cause; now 3 do (0.75 %), and none yields a finding.
  const Setup s = chain_setup();
  const boost::math::chi_squared chi2(10.0);
  int off_floor = 0;
  for (unsigned seed = 1; seed <= 400; ++seed) {
    TempDir dir;
    const auto r = run(make_case(dir, s, "", s.text, {}, seed));
    CHECK_MESSAGE(r.findings.empty(), seed, "\n", explain(r));
    off_floor += r.at_noise_floor ? 0 : 1;
    if (seed != 58) continue;
    // Seed 58: the worst span lies between the two limits (the old rule's, the new one's).
    const double worst = r.baseline.worst_window_rmse();
    double points = 0.0;
    for (const auto& [name, m] : r.baseline.nodes)
      points += static_cast<double>(m.points);
    const auto limit = [&](double spans) {
      return r.noise_floor *
             std::sqrt(boost::math::quantile(boost::math::complement(chi2, 0.01 / spans)) / 10.0);
    };
    CHECK(worst > limit(points / 10.0));
    CHECK(worst <= limit(points));
    CHECK(r.at_noise_floor);
  }
  CHECK(off_floor <= 6); // 1.5 % of 400: the bound's 1 % with room for the draw
}

namespace {

// ------------------------------------- network C: a radiator panel facing a cold sky, one case

const char* const kRadiator = R"(model radiator
boundary mount T = 20
boundary sky T = -120
node panel C = 1500 [J/K] T0 = 20
node box C = 1200 [J/K] T0 = 20
node card C = 400 [J/K] T0 = 20
conductance g1 card box G = 1.5 [W/K]
conductance g2 box mount G = 0.6 [W/K]
conductance g3 panel box G = 0.4 [W/K]
radiation r1 box sky GR = 0.002 [m^2]
heater hc card P = step(0: 30 [W], 4000: 5 [W])
heater hp panel P = pwl(0: 0 [W], 2500: 80 [W], 5000: 0 [W])
{EXTRA}
case run { duration = 3 [h]; output = 60 {DATA:run} }
)";

} // namespace

TEST_CASE("diagnose radiator: radiation to a cold boundary over a wide span is named radiation") {
  TempDir dir;
  const Setup s{kRadiator, {"run"}, {"panel", "box", "card"}, 0.05};
  const auto r = run(make_case(dir, s, "radiation hid panel sky GR = 0.03 [m^2]", s.text));
  const Finding& f = top(r);
  CHECK(f.candidate.kind == "missing_link");
  CHECK_MESSAGE(same_pair(f, "panel", "sky"), explain(r));
  CHECK_MESSAGE(f.candidate.mechanism == "radiation", diagnosis_text(r));
  CHECK_MESSAGE(f.mechanism_identified, diagnosis_text(r));
  CHECK(f.mechanism_z >= 3.0);
  CHECK(value(f, "GR") == doctest::Approx(0.03).epsilon(0.1));
  // A linear link to the same cold boundary is named linear.
  TempDir dir2;
  const auto r2 = run(make_case(dir2, s, "conductance hid panel sky G = 0.25 [W/K]", s.text));
  const Finding& g = top(r2);
  CHECK_MESSAGE(same_pair(g, "panel", "sky"), explain(r2));
  CHECK_MESSAGE(g.candidate.mechanism == "linear", diagnosis_text(r2));
  CHECK_MESSAGE(g.mechanism_identified, diagnosis_text(r2));
}
