// Runs that fail at an input and the values that explain them (issue 51): an input whose corners
// take the integrator's steps is named at its place in the model, a pole of an expression too; a
// sensor leaves the network it reads as it is; the unit helpers behind the messages.

#include "kernel/core/element_registry.hpp"
#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/evaluator.hpp"
#include "lang/model.hpp"
#include "lang/schema.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

namespace {

using namespace thermnet;

/// The model's case network.
lang::NetworkSpec network_of(const test::TempDir& dir, const std::string& text) {
  test::LoadedModel m(dir.write("m.tnet", text), test::Lint::clean);
  return m.model->instantiate("c");
}

/// A table of `rows` rows one second apart.
std::string table_csv(int rows) {
  std::string s = "time,P\n";
  for (int k = 0; k < rows; ++k)
    s += std::to_string(k) + "," + std::to_string(5 + k % 2) + "\n";
  return s;
}

} // namespace

TEST_CASE("input failures: a table whose rows take the steps is named at its place") {
  test::TempDir dir("inputs");
  dir.write("p.csv", table_csv(3000));
  Network net(network_of(dir, "boundary room T = 20\nnode a C = 100\n"
                              "conductance g a room G = 1\n"
                              "heater h a P = table(\"p.csv\", \"P\")\n"
                              "case c { duration = 2999 }\n"));
  std::vector<double> T = net.initial_state();
  SolverOptions opt;
  // Steps of at most 0.02 s: each of the 2,999 segments takes 50 steps or more, beyond the 20 a
  // restart may take besides max_steps.
  opt.max_step = 0.02;
  opt.max_steps = 1000;
  try {
    integrate(net, T, 0.0, 2999.0, {}, nullptr, opt);
    FAIL("expected the run to fail");
  } catch (const lang::ModelError& e) {
    const std::string what = e.what();
    CAPTURE(what);
    CHECK(e.diag.code == "too-large");
    CHECK(what.find("P of heater 'h' jumps or bends") != std::string::npos);
    REQUIRE(e.diag.at);
    CHECK(e.diag.at->begin > 0); // the heater's statement, not the start of the file
  }
}

TEST_CASE("input failures: a table of many rows is integrated within the step budget") {
  test::TempDir dir("inputs");
  dir.write("p.csv", table_csv(3000));
  Network net(network_of(dir, "boundary room T = 20\nnode a C = 100\n"
                              "conductance g a room G = 1\n"
                              "heater h a P = table(\"p.csv\", \"P\")\n"
                              "case c { duration = 2999 }\n"));
  std::vector<double> T = net.initial_state();
  SolverOptions opt;
  opt.max_steps = 100; // far below the ~3 steps each of the 2,999 restarts takes
  const SolverStats st = integrate(net, T, 0.0, 2999.0, {}, nullptr, opt);
  CHECK(st.steps > 100);
  CHECK(st.restarts >= 2998);
  // The mean power 5.5 W through 1 W/K: a settles near 25.5 degC.
  CHECK(std::abs(T[0] - (273.15 + 25.5)) < 0.6);
}

TEST_CASE("input failures: a pole of an expression is named at the expression") {
  test::TempDir dir("inputs");
  Network net(network_of(dir, "boundary room T = 20\nnode a C = 100\n"
                              "conductance g a room G = 1\n"
                              "heater h a P = 5 * tan(time / 100)\n"
                              "case c { duration = 600 }\n"));
  std::vector<double> T = net.initial_state();
  try {
    integrate(net, T, 0.0, 600.0, {}, nullptr);
    FAIL("expected the run to fail");
  } catch (const lang::ModelError& e) {
    const std::string what = e.what();
    CAPTURE(what);
    CHECK(e.diag.code == "invalid-value");
    CHECK(what.find("grows without bound near t = 157.07") != std::string::npos);
  }
}

TEST_CASE("input failures: a jump or a steep rise is not taken for a pole") {
  test::TempDir dir("inputs");
  const std::string base = "boundary room T = 20\nnode a C = 100\nconductance g a room G = 1\n";
  Network jump(network_of(dir, base + "heater h a P = 1e9 * step(0: 0, 100: 1) + 0 * time\n"
                                      "case c { duration = 600 }\n"));
  CHECK_NOTHROW(jump.explain_failure(100.0, 0.0, 600.0, false));
  CHECK_NOTHROW(jump.explain_failure(100.0 + 1e-9, 0.0, 600.0, false));
  Network rise(
      network_of(dir, base + "heater h a P = exp(time / 10)\ncase c { duration = 600 }\n"));
  CHECK_NOTHROW(rise.explain_failure(590.0, 0.0, 600.0, false));
  Network pole(
      network_of(dir, base + "heater h a P = 1 / (time - 100)\ncase c { duration = 600 }\n"));
  CHECK_THROWS_AS(pole.explain_failure(100.0 - 1e-12, 0.0, 600.0, false), lang::ModelError);
  CHECK_NOTHROW(pole.explain_failure(300.0, 0.0, 600.0, false));
}

TEST_CASE("input failures: a sensor's lag leaves its node's temperatures as they are") {
  test::TempDir dir("inputs");
  const std::string base = "boundary room T = 20\nnode a C = 100\nconductance g a room G = 1\n"
                           "heater h a P = 5\n";
  const std::string cs = "case c { duration = 300 }\n";
  SolverOptions tight;
  tight.rtol = 1e-10;
  tight.atol = 1e-10;
  Network plain(network_of(dir, base + cs));
  std::vector<double> T0 = plain.initial_state();
  integrate(plain, T0, 0.0, 300.0, {}, nullptr, tight);
  for (const char* tau : {"1e-4", "0.01", "1", "100"}) {
    CAPTURE(tau);
    Network lagged(network_of(dir, base + "sensor s a tau = " + tau + "\n" + cs));
    REQUIRE(lagged.size() == 2); // the node and the sensor's reading
    // The Jacobian row of the node: dF_a/dT_a = -1 W/K whatever the lag.
    std::vector<double> x = lagged.initial_state(), J(lagged.jacobian_pattern().nnz());
    lagged.jacobian(0.0, x.data(), J.data());
    const SparsityPattern& p = lagged.jacobian_pattern();
    for (int k = p.row_ptr[0]; k < p.row_ptr[1]; ++k)
      CHECK(J[static_cast<std::size_t>(k)] == doctest::Approx(p.col_idx[k] == 0 ? -1.0 : 0.0));
    integrate(lagged, x, 0.0, 300.0, {}, nullptr);
    CHECK(x[0] == doctest::Approx(T0[0]).epsilon(1e-5));
  }
}

TEST_CASE("input failures: the helpers of the messages") {
  lang::KeySchema fraction;
  fraction.min = 0.0;
  fraction.max = 1.0;
  CHECK(lang::format_outside(1.5, fraction, lang::Dimension{}) == "1.5");
  CHECK(lang::format_outside(1.0 + 1e-12, fraction, lang::Dimension{}) == "1.000000000001");
  CHECK(lang::format_outside(std::nextafter(1.0, 2.0), fraction, lang::Dimension{}) ==
        "1.0000000000000002");
  CHECK_FALSE(lang::unresolved_lag(0.0, 3000.0));
  CHECK_FALSE(lang::unresolved_lag(1e-3, 3000.0));
  CHECK(lang::unresolved_lag(1e-6, 3000.0));
  CHECK_FALSE(lang::unresolved_lag(1e-6, std::nullopt));
  CHECK(lang::unresolved_lag(4e-320, std::nullopt));
}
