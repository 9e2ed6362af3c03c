// The exact discretisation of linear networks (integrate_exact) against CVODE at tight
// tolerances, on the inputs it claims (steps, pwl, tables, sums and constant multiples of them and
// of the time), and the networks it must leave to CVODE (radiation, a product of inputs, sin).

#include "kernel/core/element_registry.hpp"
#include "kernel/core/exact_linear.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "kernel/core/symmetric_modes.hpp"
#include "lang/model.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
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

/// The error of an exact-path run that must cross 0 K (failing the test if it ends silently).
thermnet::SolverError below_zero_error(Network& net) {
  thermnet::SimulationOptions opt;
  opt.solver.exact_linear_max = 64;
  try {
    (void)thermnet::simulate(net, opt);
  } catch (const thermnet::SolverError& e) {
    CHECK(std::string(e.what()).find("absolute zero") != std::string::npos);
    return e;
  }
  FAIL("the run went below 0 K silently");
  throw std::logic_error("unreachable");
}

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
  CHECK(std::string(below_zero_error(net).what()).find("a") != std::string::npos);
}

TEST_CASE("exact linear path: a link switched by a step schedule, one matrix per state") {
  // A lid opened twice (and half-open once), output times off its corners, a heater stepping
  // inside an open period: the system matrix changes at the corners only.
  const std::string text = std::string(kHeader) + R"(
switched_conductance lid a out G = 2.5 on = step(0: 0, 1234: 1, 2500: 0, 6100: 0.5, 7000: 1, 8000: 0)
heater h a P = step(0: 10, 6500: 40)
case c { duration = 10000; output = 333 }
)";
  Network net = network_of(text);
  CHECK_FALSE(net.piecewise_linear());
  CHECK(net.piecewise_affine());
  CHECK(exact_vs_cvode(text) < 1e-5);
  thermnet::SimulationOptions opt;
  opt.solver.exact_linear_max = 64;
  const auto run = thermnet::simulate(net, opt);
  CHECK(run.stats.jac_evals > 1); // a matrix read on every interval
}

TEST_CASE("exact linear path: a link switched by a ramp is left to the integrator") {
  const std::string text = std::string(kHeader) + R"(
switched_conductance lid a out G = 2.5 on = pwl(0: 0, 5000: 1)
case c { duration = 10000; output = 100 }
)";
  Network net = network_of(text);
  CHECK_FALSE(net.piecewise_affine());
  thermnet::SimulationOptions opt;
  opt.solver.exact_linear_max = 64;
  CHECK(thermnet::simulate(net, opt).stats.integrator != "exact-linear");
}

TEST_CASE("symmetric modes: the steps of a reciprocal network equal the matrix exponential's") {
  // Three nodes of capacities 1e-1 .. 1e4 J/K (modes from 1e-4 to 30 1/s), a fourth coupled weakly
  // (a mode near 0), one without a path to a boundary (an eigenvalue 0 exactly).
  Eigen::MatrixXd J(4, 4);
  J << -3.2, 1.2, 2.0, 0.0, //
      1.2, -1.3, 0.1, 0.0,  //
      2.0, 0.1, -2.1, 1e-6, //
      0.0, 0.0, 1e-6, -1e-6;
  const Eigen::Vector4d C(0.1, 50.0, 1e4, 3.0);
  const Eigen::MatrixXd A = C.cwiseInverse().asDiagonal() * J;
  const auto modes = thermnet::SymmetricModes::of(A, C);
  REQUIRE(modes.has_value());
  for (double h : {1e-3, 0.37, 3.0, 2999.9}) {
    INFO("h = " << h);
    const auto a = modes->step(h), b = thermnet::linear_step(A, h);
    CHECK((a.Phi - b.Phi).cwiseAbs().maxCoeff() <
          1e-11 * std::max(1.0, b.Phi.cwiseAbs().maxCoeff()));
    CHECK((a.Psi0 - b.Psi0).cwiseAbs().maxCoeff() <
          1e-11 * std::max(1.0, b.Psi0.cwiseAbs().maxCoeff()));
    CHECK((a.Psi1 - b.Psi1).cwiseAbs().maxCoeff() <
          1e-11 * std::max(1.0, b.Psi1.cwiseAbs().maxCoeff()));
  }
  // Not reciprocal (a sensor's lag reads a node without acting on it): no modes.
  Eigen::MatrixXd L = A;
  L(3, 0) = 0.5;
  CHECK_FALSE(thermnet::SymmetricModes::of(L, C).has_value());
}

TEST_CASE("exact linear path: a switched network driven below 0 K fails there, naming the node") {
  // The crossing is bisected with the matrix of the lid's state at the time, not the first one.
  const std::string text = std::string(kHeader) + R"(
switched_conductance lid a out G = 2.5 on = step(0: 0, 50: 1)
heater h a P = -2000
case c { duration = 10000; output = 100 }
)";
  Network net = network_of(text);
  REQUIRE(net.piecewise_affine());
  CHECK(below_zero_error(net).time > 50.0); // crossed with the lid open
}
