#include "kernel/simulation.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace thermnet {

std::vector<double> output_times(double duration, double interval) {
  std::vector<double> t;
  auto n = static_cast<long>(std::floor(duration / interval * (1 + 1e-12)));
  t.reserve(static_cast<std::size_t>(n) + 2);
  for (long k = 0; k <= n; ++k)
    t.push_back(static_cast<double>(k) * interval);
  if (duration - t.back() > 1e-9 * duration)
    t.push_back(duration);
  else
    t.back() = duration;
  return t;
}

SimulationResult simulate(Network& net, const SimulationOptions& opt) {
  const auto& settings = net.spec().settings;
  SimulationResult r;
  for (const auto& n : net.spec().nodes)
    r.names.push_back(n.name);
  std::vector<double> T = net.initial_state();
  auto record = [&](double t, const std::vector<double>& x) {
    std::vector<double> all(net.spec().nodes.size());
    net.expand(t, x.data(), all.data());
    r.times.push_back(t);
    r.temps.push_back(std::move(all));
  };
  if (opt.steady || settings.initial_steady) {
    r.stats = solve_steady(net, T, 0.0, opt.solver);
    if (opt.steady) {
      record(0.0, T);
      return r;
    }
  }
  std::optional<double> duration = opt.duration ? opt.duration : settings.duration;
  if (!duration)
    throw std::invalid_argument(
        fmt::format("case '{}' has no duration; give one with --duration", settings.name));
  if (!(*duration > 0)) throw std::invalid_argument("the duration must be positive");
  double interval = opt.output.value_or(settings.output.value_or(*duration / 1000.0));
  if (!(interval > 0)) throw std::invalid_argument("the output interval must be positive");
  if (*duration / interval > 1e7)
    throw std::invalid_argument(fmt::format(
        "{:g} output rows requested; use a longer output interval", *duration / interval));
  std::vector<double> times = output_times(*duration, interval);
  r.times.reserve(times.size());
  r.temps.reserve(times.size());
  SolverStats s = integrate(net, T, 0.0, *duration, times, record, opt.solver);
  if (settings.initial_steady) s.steps += r.stats.steps;
  r.stats = s;
  return r;
}

} // namespace thermnet
