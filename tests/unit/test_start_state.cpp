// Every command that runs a case starts it from the same state (start_state): with
// `initial = steady` and a thermostat whose steady state holds only with the heater on, simulate,
// calibrate, diagnose, sensitivity, uncertainty and estimate all begin at that state (18 degC,
// heater on), not at the boundary temperature with the heater off.

#include "kernel/calibration/calibration_problem.hpp"
#include "kernel/calibration/sensitivity.hpp"
#include "kernel/calibration/uncertainty_bands.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/estimation/estimator.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

namespace {

using namespace thermnet;

// box loses G (T - T_amb) to amb at 0 degC; the thermostat heats it with 18 W below 17 degC until
// 20 degC. Heater on, the steady state is 18 degC (inside the band: on stays consistent); heater
// off it would be 0 degC, below the switch-on point (inconsistent). lid follows box.
constexpr const char* kModel = R"(model start
param G = 1 [W/K] range 0.5 .. 2
boundary amb T = pwl(0: 0, 1000: -5)
node box C = 1000 [J/K]
node lid C = 200 [J/K]
conductance loss box amb G = G
conductance join box lid G = 2
thermostat th box P = 18 [W] on = 17 off = 20
case c { duration = 1000 ; output = 100 ; initial = steady ; data "data.csv" }
)";

// Not the model's own curve: 0.3 K off and a slow drift, so that nothing fits exactly.
std::string data_csv() {
  std::string s = "time,box,lid\n";
  for (int k = 0; k <= 10; ++k)
    s += std::to_string(100 * k) + "," + std::to_string(18.3 - 0.2 * k) + "," +
         std::to_string(18.1 - 0.25 * k) + "\n";
  return s;
}

constexpr double kSteadyBox = 273.15 + 18.0;

} // namespace

TEST_CASE("start state: every command starts a thermostat case at its consistent steady state") {
  test::TempDir dir("start");
  dir.write("data.csv", data_csv());
  test::LoadedModel m(dir.write("start.tnet", kModel), test::Lint::clean);
  const lang::Model& model = *m.model;
  const std::size_t box = 1; // spec order: amb, box, lid

  SUBCASE("simulate, and the heater stays on (the transient does not reset it)") {
    Network net(model.instantiate("c"));
    SimulationResult r = simulate(net);
    CHECK(r.temps.front()[box] == doctest::Approx(kSteadyBox).epsilon(1e-9));
    // Heater on and amb falling 5 K: box ends near 18 - 5 G/(G + ...)... at least above 14 degC;
    // with the heater off it would fall towards -5 degC.
    CHECK(r.temps.back()[box] > 273.15 + 14.0);
  }
  SUBCASE("calibrate") {
    CalibrationProblem p(model);
    auto cmp = p.compare(p.initial());
    REQUIRE(cmp.size() == 1);
    REQUIRE(cmp[0].measured.times.front() == 0.0);
    for (std::size_t s = 0; s < cmp[0].simulated.size(); ++s)
      CHECK(cmp[0].simulated[s].front() == doctest::Approx(kSteadyBox).epsilon(1e-7));
  }
  SUBCASE("diagnose") {
    DiagnosisOptions o;
    o.threads = 1;
    DiagnosisReport rep = diagnose(model, o);
    REQUIRE(!rep.curves.empty());
    for (const auto& [node, series] : rep.curves.front().before)
      CHECK(series.front() == doctest::Approx(kSteadyBox).epsilon(1e-7));
  }
  SUBCASE("sensitivity and uncertainty run simulate()") {
    SensitivityOptions so;
    so.threads = 1;
    SensitivityReport s = compute_sensitivities(model, so);
    // A thermostat switched on at the start: dT/dG at the steady state is -P/G^2 = -18 K per W/K,
    // over the range 1.5 W/K; reached only if the runs start heater-on.
    CHECK(std::abs(s.matrix.at(0).at(0)) > 1.0);
    UncertaintyOptions u;
    u.samples = 4;
    u.threads = 1;
    UncertaintyBands b = run_uncertainty(model, "c", u);
    CHECK(b.nominal.temps.front()[box] == doctest::Approx(kSteadyBox).epsilon(1e-9));
  }
  SUBCASE("estimate (ekf): its prior is the start state") {
    auto spec = model.instantiate("c");
    const auto* plugin = EstimatorRegistry::global().find("ekf");
    REQUIRE(plugin != nullptr);
    EstimatorContext ctx;
    ctx.columns = {"time", "lid"};
    ctx.network = &spec;
    auto est = plugin->create(ctx);
    // lid measured at its steady value: box, unmeasured and uncorrelated at t = 0, keeps its prior.
    auto rows = est->push({0.0, 18.0});
    REQUIRE(!rows.empty());
    CHECK(rows.front().values[0] == doctest::Approx(18.0).epsilon(1e-9));
  }
}
