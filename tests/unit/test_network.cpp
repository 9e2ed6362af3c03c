// Unit tests of the network assembly: constant-conductance links stamped in flat arrays
// (LinkBatch) and the Network's analytic Jacobian against finite differences of its heat balance.

#include "kernel/core/element_registry.hpp"
#include "kernel/core/link_batch.hpp"
#include "kernel/core/network.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"
#include "lang/source.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace {

using thermnet::JacobianLayout;
using thermnet::LinkBatch;
using thermnet::Network;

/// Hands out one slot per distinct (row, col) pair of a 3-node network, row-major.
class DenseLayout final : public JacobianLayout {
public:
  int slot(int row, int col) override { return 3 * row + col; }
};

/// A mixed network: links (plain, series, parallel), radiation, a heater, a T-dependent
/// convection correlation and two boundaries, one of them stepping.
constexpr const char* kMixedModel = R"(model mixed
boundary sink T = -100
boundary wall T = step(0: 10, 50: 30)
node a C = 10 T0 = 40
node b C = 20 T0 = 5
node c C = 5 T0 = 60
conductance g_ab a b G = 0.7
series s_bc b c { contact h = 1000 A = 1e-3 ; conduction k = 2 L = 0.01 A = 1e-3 }
parallel p_ca c a { conductance G = 0.2 ; convection h = 5 A = 0.01 }
radiation r_a a sink GR = 0.01
radiation r_cb c b GR = 0.002
cavity_convection cv b wall A = 0.01 gap = 0.02 H = 0.1
heater h_b b P = step(0: 1, 20: 3)
conductance g_cw c wall G = 0.3
)";

} // namespace

TEST_CASE("LinkBatch: flows conserve heat and the Jacobian is the negative Laplacian") {
  LinkBatch links;
  links.add(0, 1, 2.0);
  links.add(1, 2, 0.5);
  links.add(2, 0, 1.5);
  DenseLayout layout;
  links.declare(layout);
  const std::array<double, 3> T = {300.0, 310.0, 290.0};
  std::array<double, 3> F = {0.0, 0.0, 0.0};
  links.stamp_flows(T.data(), F.data());
  CHECK(F[0] == doctest::Approx(-2.0 * (300 - 310) - 1.5 * (300 - 290)));
  CHECK(F[1] == doctest::Approx(2.0 * (300 - 310) - 0.5 * (310 - 290)));
  CHECK(F[0] + F[1] + F[2] == doctest::Approx(0.0).epsilon(1e-12));
  std::array<double, 9> J{};
  links.stamp_jacobian(J.data());
  const std::array<double, 9> expected = {-3.5, 2.0, 1.5, 2.0, -2.5, 0.5, 1.5, 0.5, -2.0};
  for (std::size_t k = 0; k < J.size(); ++k)
    CHECK(J[k] == doctest::Approx(expected[k]));
}

TEST_CASE("Network: analytic Jacobian matches finite differences of the heat balance") {
  thermnet::lang::SourceManager sources;
  thermnet::lang::DiagnosticEngine diags(sources);
  auto model = thermnet::lang::Model::from_text("mixed.tnet", kMixedModel,
                                                thermnet::element_catalog(), sources, diags);
  REQUIRE(diags.error_count() == 0);
  Network net(model->instantiate());
  const int n = net.size();
  REQUIRE(n == 3);
  const auto& p = net.jacobian_pattern();
  std::vector<double> values(static_cast<std::size_t>(p.nnz()));
  for (double t : {10.0, 70.0}) {
    std::vector<double> T = {313.0, 280.0, 333.0};
    net.jacobian(t, T.data(), values.data());
    std::map<std::pair<int, int>, double> analytic;
    for (int r = 0; r < n; ++r)
      for (int q = p.row_ptr[static_cast<std::size_t>(r)];
           q < p.row_ptr[static_cast<std::size_t>(r) + 1]; ++q)
        analytic[{r, p.col_idx[static_cast<std::size_t>(q)]}] = values[static_cast<std::size_t>(q)];
    std::vector<double> Fp(3), Fm(3);
    for (int c = 0; c < n; ++c) {
      const double h = 1e-4;
      std::vector<double> Tp = T, Tm = T;
      Tp[static_cast<std::size_t>(c)] += h;
      Tm[static_cast<std::size_t>(c)] -= h;
      net.heat_balance(t, Tp.data(), Fp.data());
      net.heat_balance(t, Tm.data(), Fm.data());
      for (int r = 0; r < n; ++r) {
        const double fd =
            (Fp[static_cast<std::size_t>(r)] - Fm[static_cast<std::size_t>(r)]) / (2.0 * h);
        const auto it = analytic.find({r, c});
        const double a = it == analytic.end() ? 0.0 : it->second;
        INFO("t = " << t << ", row " << r << ", column " << c);
        CHECK(a == doctest::Approx(fd).epsilon(1e-6));
      }
    }
    // Heat balance: what the unknowns gain equals the sources minus what the boundaries take.
    std::vector<double> F(3);
    net.heat_balance(t, T.data(), F.data());
    const double gain = F[0] + F[1] + F[2];
    CHECK(gain == doctest::Approx(net.source_power(t, T.data()) - net.boundary_loss(t, T.data()))
                      .epsilon(1e-9));
  }
}

TEST_CASE("ElementRegistry: a kind must be a writable name, not a keyword, with 1 or 2 terminals") {
  using thermnet::ElementPlugin;
  using thermnet::RegistryError;
  const ElementPlugin* conductance = thermnet::ElementRegistry::global().find("conductance");
  REQUIRE(conductance);
  const auto kind = [&](std::string name, int terminals = 2) {
    ElementPlugin p = *conductance;
    p.schema.kind = std::move(name);
    p.schema.terminals = terminals;
    return p;
  };
  thermnet::ElementRegistry local;
  local.add(kind("my_link"));
  CHECK_THROWS_AS(local.add(kind("my_link")), RegistryError);
  CHECK_THROWS_AS(local.add(kind("2link")), RegistryError);
  CHECK_THROWS_AS(local.add(kind("my-link")), RegistryError);
  CHECK_THROWS_AS(local.add(kind("node")), RegistryError);
  CHECK_THROWS_AS(local.add(kind("three", 3)), RegistryError);
  ElementPlugin no_factory = kind("empty");
  no_factory.create = nullptr;
  CHECK_THROWS_AS(local.add(no_factory), RegistryError);
  CHECK(local.names() == std::vector<std::string>{"my_link"});
  const thermnet::ElementCatalogView view(local);
  REQUIRE(view.find("my_link"));
  CHECK(view.find("my_link")->terminals == 2);
  CHECK_FALSE(view.find("conductance"));
}
