// simulate_sensitivities(): a case with forward sensitivities, the parameters that move nothing
// left out of the integration.

#include "kernel/core/case_sensitivities.hpp"

#include "kernel/core/integrator.hpp"
#include "kernel/core/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace thermnet {

namespace {

/// Some parameters of another ParameterDerivatives.
class Subset final : public ParameterDerivatives {
public:
  Subset(ParameterDerivatives& all, std::vector<int> which) : all_(all), which_(std::move(which)) {}
  int count() const override { return static_cast<int>(which_.size()); }
  double scale(int j) const override { return all_.scale(map(j)); }
  void heat_balance(int j, double t, const double* T, double* dF) override {
    all_.heat_balance(map(j), t, T, dF);
  }
  const std::vector<double>& capacities(int j) const override { return all_.capacities(map(j)); }
  const std::vector<double>& initial_state(int j) const override {
    return all_.initial_state(map(j));
  }

private:
  int map(int j) const { return which_[static_cast<std::size_t>(j)]; }
  ParameterDerivatives& all_;
  std::vector<int> which_;
};

} // namespace

std::optional<NodeSensitivities>
simulate_sensitivities(lang::NetworkSpec spec, std::vector<MovedSpec> moved,
                       const std::vector<double>& times, const std::vector<int>& nodes,
                       const SolverOptions& solver, std::string* why_not) {
  Network net(std::move(spec));
  NetworkDerivatives all(net, std::move(moved));
  if (!all.supported()) {
    if (why_not) *why_not = all.why_not();
    return std::nullopt;
  }
  std::vector<int> live;
  for (int j = 0; j < all.count(); ++j)
    if (!all.inert(j)) live.push_back(j);
  Subset d(all, live);

  NodeSensitivities out;
  const auto ns = static_cast<std::size_t>(all.count());
  out.dT.assign(ns, {});
  if (times.empty()) return out;
  std::vector<double> T = start_state(net, solver);
  std::vector<std::vector<double>> S;
  for (int j : live)
    S.push_back(all.initial_state(j));
  std::vector<double> node_T(net.spec().nodes.size()), node_S(node_T.size());
  const auto sample = [&](const std::vector<double>& values, std::vector<double>& row) {
    row.resize(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i)
      row[i] = values[static_cast<std::size_t>(nodes[i])];
  };
  out.stats = integrate(
      net, d, T, S, 0.0, times.back(), times,
      [&](double t, const std::vector<double>& x, const std::vector<std::vector<double>>& s) {
        net.expand(t, x.data(), node_T.data());
        out.T.emplace_back();
        sample(node_T, out.T.back());
        for (std::size_t j = 0; j < ns; ++j) {
          auto& rows = out.dT[j];
          rows.emplace_back(nodes.size(), 0.0);
          const auto it = std::find(live.begin(), live.end(), static_cast<int>(j));
          if (it == live.end()) continue;
          // The unknowns' sensitivities, and the boundaries' derivatives for boundary nodes.
          const std::vector<double>& sj = s[static_cast<std::size_t>(it - live.begin())];
          net.expand(t, sj.data(), node_S.data());
          all.boundary_derivative(static_cast<int>(j), t, node_S.data());
          sample(node_S, rows.back());
        }
      },
      solver);
  if (out.T.size() != times.size())
    throw std::runtime_error(
        fmt::format("the simulation gave {} of the {} times", out.T.size(), times.size()));
  return out;
}

} // namespace thermnet
