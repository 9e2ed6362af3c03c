// Unit tests of the forward sensitivities (CVODES, kernel/core/case_sensitivities.hpp): for every
// element kind, a param in one of its keys is differentiated through the elaboration, the kind's
// key derivative or the difference of its two builds, and the integrated dT/dp must match central
// differences of two tight simulations; capacities, boundary and initial temperatures too; what
// cannot be differentiated is reported, not guessed.
#include "kernel/core/case_sensitivities.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

namespace {

using namespace thermnet;

/// A two-node network heated by a step, coupled to an ambient boundary, with `element` (a line
/// naming param p) between them or on them; `extra` adds lines. Nodes a (heated) and b.
std::string model_text(const std::string& param, const std::string& element,
                       const std::string& extra = "") {
  return "model sens\n" + param +
         "\n"
         "boundary env T = pwl(0: 20, 2000: 26)\n"
         "node a C = 400 [J/K] T0 = 25\n"
         "node b C = 900 [J/K] T0 = 18\n"
         "conductance ga a env G = 0.05 [W/K]\n"
         "conductance gb b env G = 0.08 [W/K]\n"
         "heater q a P = step(0: 3, 900: 8, 2400: 1)\n" +
         element + "\n" + extra + "case run { duration = 3600; output = 60 }\n";
}

struct Compared {
  double largest = 0.0;    ///< largest |dT/dp| * scale, K
  double difference = 0.0; ///< largest |sensitivity - central difference| * scale, K
  std::size_t differenced = 0;
  std::size_t moved = 0;
};

/// The sensitivities of nodes a and b to param p at `value`, against central differences of two
/// simulations at rtol = atol = 1e-11 (the sensitivities' own run at 1e-9).
Compared compare(const std::string& text, double value) {
  test::TempDir dir;
  test::LoadedModel m(dir.write("m.tnet", text), test::Lint::clean);
  const lang::NetworkSpec spec = m.model->instantiate("run", {{"p", value}});
  const std::vector<double> times = output_times(3600.0, 60.0);
  const std::vector<int> nodes = {spec.node_index("a"), spec.node_index("b")};
  const double scale = std::abs(value), h = 1e-7 * scale;
  MovedSpec moved;
  moved.spec = m.model->instantiate("run", {{"p", value + h}});
  moved.step = h;
  moved.scale = scale;
  SolverOptions tight;
  tight.rtol = tight.atol = 1e-9;
  tight.sensitivity_tolerance = 1e-9;
  Compared out;
  {
    Network net(spec);
    NetworkDerivatives d(net, {moved});
    REQUIRE_MESSAGE(d.supported(), d.why_not());
    out.moved = d.moved_pieces(0);
  }
  std::string why;
  const auto s = simulate_sensitivities(spec, {moved}, times, nodes, tight, &why);
  REQUIRE_MESSAGE(s.has_value(), why);
  const auto run = [&](double v) {
    Network net(m.model->instantiate("run", {{"p", v}}));
    SolverOptions o;
    o.rtol = o.atol = 1e-11;
    std::vector<double> T = start_state(net, o), all(net.spec().nodes.size());
    std::vector<std::vector<double>> rows;
    integrate(
        net, T, 0.0, times.back(), times,
        [&](double t, const std::vector<double>& x) {
          net.expand(t, x.data(), all.data());
          rows.push_back(
              {all[static_cast<std::size_t>(nodes[0])], all[static_cast<std::size_t>(nodes[1])]});
        },
        o);
    return rows;
  };
  const double dh = 1e-4 * scale;
  const auto up = run(value + dh), down = run(value - dh);
  REQUIRE(s->T.size() == times.size());
  for (std::size_t k = 0; k < times.size(); ++k)
    for (std::size_t i = 0; i < 2; ++i) {
      const double fd = (up[k][i] - down[k][i]) / (2 * dh);
      out.largest = std::max(out.largest, std::abs(fd) * scale);
      out.difference = std::max(out.difference, std::abs(fd - s->dT[0][k][i]) * scale);
    }
  // (the differenced pieces are counted after the run: a kind refusing the rates at run time)
  {
    Network net(spec);
    NetworkDerivatives d(net, {moved});
    std::vector<double> dF(static_cast<std::size_t>(net.size()));
    std::vector<double> T0 = net.initial_state();
    d.heat_balance(0, 100.0, T0.data(), dF.data());
    out.differenced = d.differenced_pieces(0);
  }
  return out;
}

/// Checks the sensitivities of one model against the central differences: the effect is real
/// (above 0.01 K over the parameter's size) and the two agree within 1e-4 of it.
void check(const std::string& what, const std::string& text, double value,
           std::size_t differenced) {
  INFO(what);
  const Compared c = compare(text, value);
  CHECK(c.largest > 0.01);
  CHECK(c.difference < 1e-4 * c.largest);
  CHECK(c.differenced == differenced);
}

TEST_CASE("sensitivities: every linear kind through its conductance") {
  const std::string p = "param p = 1 range 0.2 .. 5";
  check("conductance G", model_text(p, "conductance x a b G = 0.3 * p"), 1.0, 0);
  check("resistor R", model_text(p, "resistor x a b R = 4 * p"), 1.0, 0);
  check("conduction k", model_text(p, "conduction x a b k = 150 * p L = 0.1 A = 2e-4"), 1.0, 0);
  check("contact h", model_text(p, "contact x a b h = 1000 * p A = 3e-4"), 1.0, 0);
  check("convection h to a boundary", model_text(p, "convection x a env h = 10 * p A = 0.02"), 1.0,
        0);
  check("cylinder_conduction r_out",
        model_text(p, "cylinder_conduction x a b k = 0.2 r_in = 0.01 r_out = 0.012 * p L = 0.5"),
        1.5, 0);
  check("series block",
        model_text(p, "series x a b { contact h = 1500 * p A = 3e-4 ; conduction k = 200 L = 3 "
                      "[mm] A = 54.8 [mm^2] }"),
        1.0, 0);
}

TEST_CASE("sensitivities: radiation, heater and switched conductance by their key derivatives") {
  const std::string p = "param p = 1 range 0.2 .. 5";
  check("radiation GR", model_text(p, "radiation x a env GR = 0.01 * p"), 1.0, 0);
  check(
      "radiation eps1",
      model_text("param p = 0.6 range 0.1 .. 0.9", "radiation x a b A = 0.02 eps1 = p eps2 = 0.8"),
      0.6, 0);
  check("radiation A and eps2 (one param in two keys)",
        model_text("param p = 0.6 range 0.1 .. 0.9",
                   "radiation x a env A = 0.05 * p eps1 = 0.9 eps2 = p"),
        0.6, 0);
  check("heater P, a step signal",
        model_text(p, "heater x b P = step(0: 2 * p, 1200: 5 * p, 3000: 0)"), 1.0, 0);
  check("switched_conductance G",
        model_text(p, "switched_conductance x a b G = 0.4 * p on = step(0: 0, 600: 1, 1800: 0)"),
        1.0, 0);
  check("parallel block of a radiation and a conductance",
        model_text(p, "parallel x a b { radiation GR = 0.02 * p ; conductance G = 0.1 }"), 1.0, 0);
}

TEST_CASE("sensitivities: correlations by their scale, the rest of their keys by differences") {
  const std::string p = "param p = 1 range 0.2 .. 5";
  check("annulus_convection scale",
        model_text(p, "annulus_convection x a b D_in = 0.02 D_out = 0.04 L = 0.3 scale = p"), 1.0,
        0);
  check("annulus_convection D_out (differenced)",
        model_text(p, "annulus_convection x a b D_in = 0.02 D_out = 0.04 * p L = 0.3"), 1.0, 1);
  check("cavity_convection scale",
        model_text(p, "cavity_convection x a b A = 0.04 gap = 0.02 scale = p"), 1.0, 0);
  check("cavity_convection gap (differenced)",
        model_text(p, "cavity_convection x a b A = 0.04 gap = 0.02 * p"), 1.0, 1);
}

TEST_CASE("sensitivities: capacities, a boundary's and an initial temperature") {
  check("capacity",
        model_text("param p = 1 range 0.2 .. 5", "node c C = 300 * p",
                   "conductance gc a c G = 0.2\nconductance gd c b G = 0.1\n"),
        1.0, 0);
  check("boundary temperature",
        model_text("param p = 30 [degC] range 0 [degC] .. 60 [degC]",
                   "boundary hot T = p\nconductance gh b hot G = 0.1 [W/K]"),
        30.0, 0);
  check("initial temperature",
        model_text("param p = 40 [degC] range 0 [degC] .. 60 [degC]", "node c C = 300 [J/K] T0 = p",
                   "conductance gc a c G = 0.2\nconductance gd c b G = 0.1\n"),
        40.0, 0);
}

TEST_CASE("sensitivities: what cannot be integrated is reported") {
  test::TempDir dir;
  test::LoadedModel m(
      dir.write("m.tnet", model_text("param p = 1 range 0.2 .. 5", "conductance x a b G = 0.3 * p",
                                     "thermostat t b P = 5 on = 15 off = 17\n")),
      test::Lint::clean);
  MovedSpec moved;
  moved.spec = m.model->instantiate("run", {{"p", 1.1}});
  moved.step = 0.1;
  std::string why;
  const auto s = simulate_sensitivities(m.model->instantiate("run", {{"p", 1.0}}), {moved},
                                        {0.0, 60.0}, {0}, SolverOptions{}, &why);
  CHECK_FALSE(s.has_value());
  CHECK(why.find("events") != std::string::npos);
}

/// A kind outside the tree that gives no key derivative: Q = k (T_a - T_b)^2 sign(T_a - T_b).
class SquareLink final : public NonlinearLink {
public:
  SquareLink(int a, int b, double k) : NonlinearLink(a, b), k_(k) {}

protected:
  double evaluate(double ta, double tb, double& dq_da, double& dq_db) const override {
    const double d = ta - tb;
    dq_da = 2 * k_ * std::abs(d);
    dq_db = -dq_da;
    return k_ * d * std::abs(d);
  }

private:
  double k_;
};

TEST_CASE("sensitivities: a plugin kind without a key derivative is differenced") {
  ElementRegistry registry;
  for (const auto& name : ElementRegistry::global().names())
    registry.add(*ElementRegistry::global().find(name));
  lang::ElementSchema s;
  s.kind = "square_link";
  s.terminals = 2;
  s.doc = "test kind";
  s.keys.push_back(Key("k", lang::dim::conductance, "strength").required().positive());
  registry.add(ElementPlugin{std::move(s), [](const lang::ElementSpec& e) {
                               return std::unique_ptr<Element>(std::make_unique<SquareLink>(
                                   e.nodes()[0], e.nodes()[1], e.number("k")));
                             }});
  // The network as the elaboration would give it, with the plugin's element added by hand.
  test::TempDir dir;
  test::LoadedModel m(dir.write("m.tnet", model_text("param p = 1 range 0.2 .. 5", "")),
                      test::Lint::clean);
  const auto with_k = [&](double k) {
    lang::NetworkSpec spec = m.model->instantiate("run");
    lang::ElementSpec e;
    e.schema = registry.find("square_link") ? &registry.find("square_link")->schema : nullptr;
    e.name = "sq";
    e.set_nodes(std::array{spec.node_index("a"), spec.node_index("b")});
    e.set("k", lang::Signal::of(k));
    spec.elements.push_back(std::move(e));
    return spec;
  };
  const double k = 0.02, h = 1e-7 * k;
  Network net(with_k(k), registry);
  NetworkDerivatives d(net, {MovedSpec{with_k(k + h), h, k}}, registry);
  REQUIRE(d.supported());
  CHECK(d.moved_pieces(0) == 1);
  // dF/dk at a state = (T_a - T_b)^2 sign: exactly the flow over k
  std::vector<double> T = net.initial_state(), dF(T.size());
  d.heat_balance(0, 0.0, T.data(), dF.data());
  CHECK(d.differenced_pieces(0) == 1);
  const double Ta = T[0], Tb = T[1], q = (Ta - Tb) * std::abs(Ta - Tb);
  CHECK(dF[0] == doctest::Approx(-q).epsilon(1e-6));
  CHECK(dF[1] == doctest::Approx(q).epsilon(1e-6));
  // integrated against central differences
  std::vector<std::vector<double>> S = {d.initial_state(0)};
  std::vector<double> T0 = start_state(net, SolverOptions{});
  std::vector<double> last_s;
  SolverOptions o;
  o.rtol = o.atol = 1e-9;
  o.sensitivity_tolerance = 1e-9;
  integrate(
      net, d, T0, S, 0.0, 3600.0, {3600.0},
      [&](double, const std::vector<double>&, const std::vector<std::vector<double>>& s) {
        last_s = s[0];
      },
      o);
  const auto final_T = [&](double kv) {
    Network n(with_k(kv), registry);
    SolverOptions t;
    t.rtol = t.atol = 1e-11;
    std::vector<double> x = start_state(n, t);
    integrate(n, x, 0.0, 3600.0, {}, nullptr, t);
    return x;
  };
  const double dk = 1e-4 * k;
  const auto up = final_T(k + dk), down = final_T(k - dk);
  for (std::size_t i = 0; i < 2; ++i) {
    const double fd = (up[i] - down[i]) / (2 * dk);
    CHECK(std::abs(fd) * k > 0.01);
    CHECK(last_s[i] == doctest::Approx(fd).epsilon(1e-4));
  }
}

} // namespace
