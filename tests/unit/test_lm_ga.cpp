// Unit tests of the lm, ga and auto optimizers, the sensitivities and the uncertainty bands, on
// small models whose "measurements" are thermnet's own simulation of known params plus noise.

#include "app/uncertainty.hpp"
#include "kernel/calibration/calibration_problem.hpp"
#include "kernel/calibration/optimizer.hpp"
#include "kernel/calibration/sensitivity.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/parallel.hpp"
#include "kernel/core/simulation.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <unistd.h>
#include <vector>

#include "temp_dir.hpp"

using thermnet::test::TempDir;

namespace {

namespace fs = std::filesystem;
using namespace thermnet;

constexpr double kZeroCelsius = 273.15;

/// A model loaded from a file (with its sources kept alive).
struct Loaded {
  lang::SourceManager sources;
  lang::DiagnosticEngine diags{sources};
  std::unique_ptr<lang::Model> model;
  /// Loads (and, unless the data are still to be written, lints) a model.
  explicit Loaded(const std::string& path, bool lint = true) {
    model = lang::Model::load(path, thermnet::element_catalog(), sources, diags);
    REQUIRE(model);
    if (lint) model->lint(diags);
    for (const auto& d : diags.all())
      INFO(d.message);
    REQUIRE(diags.error_count() == 0);
  }
  Loaded(const Loaded&) = delete;
};

/// Standard normal deviate number k of a stream (Box-Muller on uniform01: reproducible).
double gauss(std::uint64_t stream, std::uint64_t k) {
  const double u1 = 1.0 - uniform01(4242, stream, 2 * k);
  const double u2 = uniform01(4242, stream, 2 * k + 1);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

/// Writes the data file of a case: the model's own simulation at `truth` plus noise sigma (K)
/// on the listed nodes.
void make_data(const lang::Model& model, const std::string& case_name,
               const lang::ParamValues& truth, const std::vector<std::string>& nodes, double sigma,
               const std::string& path) {
  Network net(model.instantiate(case_name, truth));
  SimulationResult r = simulate(net);
  std::string csv = "time";
  for (const auto& n : nodes)
    csv += "," + n;
  csv += "\n";
  for (std::size_t k = 0; k < r.times.size(); ++k) {
    csv += fmt::format("{:.10g}", r.times[k]);
    for (std::size_t c = 0; c < nodes.size(); ++c) {
      const auto i = static_cast<std::size_t>(net.spec().node_index(nodes[c]));
      csv += fmt::format(",{:.10f}", r.temps[k][i] - kZeroCelsius + sigma * gauss(c, k));
    }
    csv += "\n";
  }
  std::ofstream(path, std::ios::binary) << csv;
}

// Two capacities heated through a conductance and cooled to ambient; three identifiable
// params declared far from the truth (Gab = 2, Gb = 0.8, Ca = 1000).
const char* const kThreeParams = R"(model three
param Gab = 0.7 [W/K] range 0.5 .. 5
param Gb = 2.5 [W/K] range 0.2 .. 3
param Ca = 2500 [J/K] range 300 .. 3000
boundary amb T = 0
node a C = Ca T0 = 20
node b C = 500 [J/K] T0 = 20
conductance gab a b G = Gab
conductance gb b amb G = Gb
heater h a P = step(0: 40, 1500: 0)
case fit { duration = 3600; output = 60; data "fit.csv" }
)";
const lang::ParamValues kTruth{{"Gab", 2.0}, {"Gb", 0.8}, {"Ca", 1000.0}};

// Two conductances in series through a massless node: only G1 G2 / (G1 + G2) is observable.
const char* const kSeries = R"(model series_pair
param G1 = 1.5 [W/K] range 0.5 .. 6
param G2 = 2.5 [W/K] range 0.5 .. 6
boundary amb T = 0
node a C = 800 [J/K] T0 = 40
node m C = 0
conductance g1 a m G = G1
conductance g2 m amb G = G2
case fit { duration = 3000; output = 60; data "fit.csv" }
)";

OptimizerResult run_method(const std::string& name, const CalibrationProblem& problem,
                           OptimizerSettings s) {
  const OptimizerPlugin* plugin = OptimizerRegistry::global().find(name);
  REQUIRE(plugin != nullptr);
  return plugin->create()->run(problem, s);
}

struct ThreeParamFit {
  TempDir dir{"lm3"};
  std::string model_path = dir.write("three.tnet", kThreeParams);
  std::unique_ptr<Loaded> loaded;
  explicit ThreeParamFit(double sigma) {
    Loaded gen(model_path, false);
    make_data(*gen.model, "fit", kTruth, {"a", "b"}, sigma, (dir.path / "fit.csv").string());
    loaded = std::make_unique<Loaded>(model_path);
  }
};

} // namespace

TEST_CASE("lm reaches the noise floor from far away with few simulations") {
  const double sigma = 0.1;
  ThreeParamFit fit(sigma);
  CalibrationProblem problem(*fit.loaded->model);
  OptimizerSettings s;
  s.threads = 2;
  OptimizerResult r = run_method("lm", problem, s);
  REQUIRE(r.found);
  MESSAGE(fmt::format("lm: RMSE {:.4f} K (sigma {}), {} simulations, params {:.4f} {:.4f} {:.2f} "
                      "(truth 2 0.8 1000), std errors {:.3g} {:.3g} {:.3g}",
                      r.rmse, sigma, r.simulations, r.best[0], r.best[1], r.best[2],
                      r.std_errors[0], r.std_errors[1], r.std_errors[2]));
  for (const auto& n : r.notes)
    MESSAGE(n);
  CHECK(r.rmse == doctest::Approx(sigma).epsilon(0.10));
  CHECK(r.best[0] == doctest::Approx(2.0).epsilon(0.10));
  CHECK(r.best[1] == doctest::Approx(0.8).epsilon(0.10));
  CHECK(r.best[2] == doctest::Approx(1000.0).epsilon(0.10));
  CHECK(r.simulations <= 120); // 1 % of the study's 12,000-sample Monte Carlo
  CHECK(r.simulations == r.evaluations * problem.cases().size());
  REQUIRE(r.std_errors.size() == 3);
  REQUIRE(r.correlation.size() == 3);
  for (std::size_t j = 0; j < 3; ++j) {
    CHECK(r.std_errors[j] > 0.0);
    CHECK(r.correlation[j][j] == doctest::Approx(1.0));
    for (std::size_t k = 0; k < 3; ++k)
      CHECK(r.correlation[j][k] == doctest::Approx(r.correlation[k][j]));
  }
  // The truth lies within a few standard errors of the estimate.
  CHECK(std::abs(r.best[0] - 2.0) < 5 * r.std_errors[0]);
  CHECK(std::abs(r.best[1] - 0.8) < 5 * r.std_errors[1]);

  SUBCASE("same result whatever the number of threads") {
    s.threads = 1;
    OptimizerResult r1 = run_method("lm", problem, s);
    CHECK(r1.best == r.best);
    CHECK(r1.evaluations == r.evaluations);
  }
  SUBCASE("the budget bounds the evaluations") {
    s.samples = 10;
    OptimizerResult rb = run_method("lm", problem, s);
    CHECK(rb.evaluations <= 10 + 3); // + the final Jacobian for the statistics
    OptimizerSettings one;
    one.samples = 1;
    CHECK(rb.rmse <= run_method("lm", problem, one).rmse);
  }
}

TEST_CASE("lm standard errors shrink with less noise") {
  ThreeParamFit noisy(0.2), quiet(0.02);
  CalibrationProblem pn(*noisy.loaded->model), pq(*quiet.loaded->model);
  OptimizerResult rn = run_method("lm", pn, {}), rq = run_method("lm", pq, {});
  REQUIRE(rn.std_errors.size() == 3);
  REQUIRE(rq.std_errors.size() == 3);
  for (std::size_t j = 0; j < 3; ++j) {
    MESSAGE(fmt::format("param {}: std error {:.3g} (sigma 0.2) vs {:.3g} (sigma 0.02)", j,
                        rn.std_errors[j], rq.std_errors[j]));
    CHECK(rq.std_errors[j] < rn.std_errors[j] / 5);
  }
}

TEST_CASE("lm's correlation matrix flags two conductances in series") {
  TempDir dir("lmser");
  const std::string path = dir.write("series.tnet", kSeries);
  {
    Loaded gen(path, false);
    make_data(*gen.model, "fit", {{"G1", 3.0}, {"G2", 1.0}}, {"a"}, 0.05,
              (dir.path / "fit.csv").string());
  }
  Loaded loaded(path);
  CalibrationProblem problem(*loaded.model);
  OptimizerResult r = run_method("lm", problem, {});
  REQUIRE(r.found);
  REQUIRE(r.correlation.size() == 2);
  MESSAGE(fmt::format("series: G1 {:.3f} G2 {:.3f}, G1 G2/(G1+G2) {:.4f} (truth 0.75), "
                      "correlation {:.6f}, RMSE {:.4f}",
                      r.best[0], r.best[1], r.best[0] * r.best[1] / (r.best[0] + r.best[1]),
                      r.correlation[0][1], r.rmse));
  CHECK(std::abs(r.correlation[0][1]) > 0.99);
  CHECK(r.best[0] * r.best[1] / (r.best[0] + r.best[1]) == doctest::Approx(0.75).epsilon(0.02));
  CHECK(r.rmse == doctest::Approx(0.05).epsilon(0.15));
}

TEST_CASE("ga improves on its initial population and does not depend on the threads") {
  ThreeParamFit fit(0.1);
  CalibrationProblem problem(*fit.loaded->model);
  OptimizerSettings s;
  s.seed = 7;
  s.samples = 40; // the initial population only (population 40, no generation)
  s.threads = 2;
  OptimizerResult initial = run_method("ga", problem, s);
  s.samples = 240;
  OptimizerResult evolved = run_method("ga", problem, s);
  s.threads = 1;
  OptimizerResult serial = run_method("ga", problem, s);
  REQUIRE(initial.found);
  REQUIRE(evolved.found);
  MESSAGE(fmt::format("ga: RMSE {:.4f} K after the initial population, {:.4f} K after {} "
                      "evaluations",
                      initial.rmse, evolved.rmse, evolved.evaluations));
  CHECK(evolved.rmse < initial.rmse);
  CHECK(serial.best == evolved.best);
  CHECK(serial.rmse == evolved.rmse);
  CHECK(evolved.evaluations == 241); // 6 x 40 + the champion's report
}

TEST_CASE("auto: lhs start, then lm") {
  ThreeParamFit fit(0.1);
  CalibrationProblem problem(*fit.loaded->model);
  OptimizerSettings s;
  s.threads = 2;
  OptimizerResult r = run_method("auto", problem, s);
  REQUIRE(r.found);
  for (const auto& n : r.notes)
    MESSAGE(n);
  MESSAGE(fmt::format("auto: RMSE {:.4f} K, {} evaluations", r.rmse, r.evaluations));
  CHECK(r.method == "auto");
  CHECK(r.rmse == doctest::Approx(0.1).epsilon(0.10));
  CHECK(r.evaluations > 60); // 20 x 3 lhs samples, then lm
  CHECK(r.std_errors.size() == 3);
  s.threads = 1;
  CHECK(run_method("auto", problem, s).best == r.best);
}

namespace {

// One node cooling to 0 degC through G (the dominant param) with a weak heater P.
const char* const kOneNode = R"(model one
param Gp = 2 [W/K] range 1 .. 3
param Pp = 0.1 [W] range 0 .. 0.2
boundary amb T = 0
node n C = 1000 [J/K] T0 = 20
conductance g n amb G = Gp
heater h n P = Pp
case run { duration = 2000; output = 10 }
)";

/// Analytic dT/dG of the one-node model at time t (K per W/K).
double dT_dG(double t, double G, double P) {
  const double C = 1000.0, T0 = 20.0, e = std::exp(-G * t / C);
  return -P / (G * G) * (1 - e) - (T0 - P / G) * (t / C) * e;
}

} // namespace

TEST_CASE("sensitivities match the analytic derivative and rank the dominant param first") {
  TempDir dir("sens");
  Loaded loaded(dir.write("one.tnet", kOneNode));
  SensitivityOptions opt;
  opt.elements = true;
  opt.threads = 2;
  SensitivityReport r = compute_sensitivities(*loaded.model, opt);
  REQUIRE(r.outputs == std::vector<std::string>{"n"});
  REQUIRE(r.factors.size() >= 4); // Gp, Pp, g.G, h.P, n.C
  CHECK(r.factors[r.ranking[0]].name == "Gp");
  double sum = 0.0;
  int count = 0;
  for (double t = 0; t <= 2000.0 + 1e-9; t += 10.0, ++count)
    sum += std::pow(dT_dG(t, 2.0, 0.1), 2);
  const double rms = std::sqrt(sum / count);
  CHECK(r.matrix[0][0] == doctest::Approx(rms * 2.0).epsilon(1e-3)); // x (hi - lo) = 2
  std::size_t g = 0;
  while (g < r.factors.size() && r.factors[g].name != "g.G")
    ++g;
  REQUIRE(g < r.factors.size());
  CHECK(r.matrix[g][0] == doctest::Approx(rms * 2.0).epsilon(1e-3)); // x |G| = 2
  CHECK(r.matrix[1][0] < r.matrix[0][0] / 10);
  CHECK(r.simulations == 1 + 2 * r.factors.size());
  opt.threads = 1;
  CHECK(compute_sensitivities(*loaded.model, opt).matrix == r.matrix);
}

TEST_CASE("uncertainty bands contain the nominal run and are deterministic") {
  TempDir dir("unc");
  Loaded loaded(dir.write("one.tnet", kOneNode));
  UncertaintyOptions opt;
  opt.samples = 40;
  opt.seed = 3;
  opt.threads = 2;
  UncertaintyBands b = run_uncertainty(*loaded.model, "", opt);
  CHECK(b.failed == 0);
  CHECK(b.params == std::vector<std::string>{"Gp", "Pp"});
  const std::size_t n = 1; // amb, n
  REQUIRE(b.names[n] == "n");
  for (std::size_t k = 0; k < b.times.size(); ++k) {
    const auto& row = b.stats[n][k];
    REQUIRE(row.size() == 5);
    const double T = b.nominal.temps[k][n];
    CHECK(row[0] <= T + 1e-4);
    CHECK(row[4] >= T - 1e-4);
    CHECK(row[0] <= row[1]);
    CHECK(row[1] <= row[2]);
    CHECK(row[2] <= row[3]);
    CHECK(row[3] <= row[4]);
  }
  const std::string csv = app::format_bands_csv(b);
  CHECK(csv.substr(0, csv.find('\n')) ==
        "time,amb_min,amb_p5,amb_p50,amb_p95,amb_max,n_min,n_p5,n_p50,n_p95,n_max");
  opt.threads = 1;
  CHECK(app::format_bands_csv(run_uncertainty(*loaded.model, "", opt)) == csv);
  CHECK(app::plot_bands_svg(b, {"n"}, "bands").find("<svg") != std::string::npos);
}

TEST_CASE("percentiles interpolate between order statistics") {
  const std::vector<double> v{1, 2, 3, 4, 5};
  CHECK(percentile_of_sorted(v, 50) == 3.0);
  CHECK(percentile_of_sorted(v, 25) == 2.0);
  CHECK(percentile_of_sorted(v, 10) == doctest::Approx(1.4));
  CHECK(app::percentile_label(2.5) == "p2.5");
}
