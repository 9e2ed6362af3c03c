// The exact discretisation of linear networks (integrate_exact) against CVODE at tight
// tolerances, on the inputs it claims (steps, pwl, tables, sums and constant multiples of them and
// of the time), and the networks it must leave to CVODE (radiation, a product of inputs, sin).

#include "kernel/core/element_registry.hpp"
#include "kernel/core/exact_linear.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/model.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace {

using thermnet::Network;

/// The network of a model text's first case.
Network network_of(const std::string& text) {
  thermnet::lang::SourceManager sources;
  thermnet::lang::DiagnosticEngine diags(sources);
  auto model =
      thermnet::lang::Model::from_text("m.tnet", text, thermnet::element_catalog(), sources, diags);
  REQUIRE(diags.error_count() == 0);
  return Network(model->instantiate("c"));
}

/// Largest difference (K) between the exact path and CVODE at 1e-10 over every node and sample.
double exact_vs_cvode(const std::string& text) {
  Network exact = network_of(text), cvode = network_of(text);
  thermnet::SimulationOptions fast, tight;
  fast.solver.exact_linear_max = 64;
  tight.solver.rtol = 1e-10;
  tight.solver.atol = 1e-10;
  const auto a = thermnet::simulate(exact, fast);
  const auto b = thermnet::simulate(cvode, tight);
  CHECK(a.stats.integrator == "exact-linear");
  CHECK(b.stats.integrator != "exact-linear");
  REQUIRE(a.times == b.times);
  double worst = 0.0;
  for (std::size_t k = 0; k < a.temps.size(); ++k)
    for (std::size_t i = 0; i < a.temps[k].size(); ++i)
      worst = std::max(worst, std::abs(a.temps[k][i] - b.temps[k][i]));
  return worst;
}

const char* const kHeader = R"(
boundary out T = pwl(0: 5, 3000: 12, 7000: 0)
node a C = 800 T0 = 20
node b C = 400 T0 = 15
conductance g1 a out G = 0.5
conductance g2 a b G = 0.8
resistor r3 b out R = 3.3
)";

} // namespace

TEST_CASE("exact linear path: steps, pwl and constant multiples of them match CVODE") {
  const std::string text = std::string(kHeader) + R"(
heater h a P = step(0: 10, 3000: 0, 5000: 5)
heater k b P = 0.3 * h.P - 2 * pwl(0: 0, 4000: 4, 9000: 1) + 0.001 * time
case c { duration = 10000; output = 100 }
)";
  CHECK(Network(network_of(text)).piecewise_linear());
  CHECK(exact_vs_cvode(text) < 1e-5);
}

TEST_CASE("exact linear path: output times off the input's corners") {
  const std::string text = std::string(kHeader) + R"(
heater h a P = step(0: 10, 3050: 0, 5033: 5)
case c { duration = 10000; output = 333 }
)";
  CHECK(exact_vs_cvode(text) < 1e-5);
}

TEST_CASE("exact linear path: networks it must leave to the integrator") {
  for (const char* heater : {"heater h a P = 5 * sin(time / 300)",
                             "heater h a P = pwl(0: 1, 9000: 3) * pwl(0: 2, 9000: 1)",
                             "heater h a P = abs(pwl(0: -1, 9000: 3))"}) {
    INFO(heater);
    const std::string text =
        std::string(kHeader) + heater + "\ncase c { duration = 10000; output = 100 }\n";
    Network net = network_of(text);
    CHECK_FALSE(net.piecewise_linear());
    thermnet::SimulationOptions opt;
    opt.solver.exact_linear_max = 64;
    CHECK(thermnet::simulate(net, opt).stats.integrator != "exact-linear");
  }
  const std::string radiating = std::string(kHeader) +
                                "radiation rad a out A = 1 eps1 = 0.9 eps2 = 1\n"
                                "case c { duration = 10000; output = 100 }\n";
  CHECK_FALSE(network_of(radiating).piecewise_linear());
}

TEST_CASE("exact linear path: a node driven below 0 K fails there, as with the integrator") {
  const std::string text = std::string(kHeader) + R"(
heater h a P = -2000
case c { duration = 10000; output = 100 }
)";
  Network net = network_of(text);
  REQUIRE(net.piecewise_linear());
  thermnet::SimulationOptions opt;
  opt.solver.exact_linear_max = 64;
  try {
    (void)thermnet::simulate(net, opt);
    FAIL("the run went below 0 K silently");
  } catch (const thermnet::SolverError& e) {
    CHECK(std::string(e.what()).find("absolute zero") != std::string::npos);
    CHECK(std::string(e.what()).find("a") != std::string::npos);
  }
}
