#include "kernel/core/simulation.hpp"

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

namespace {

/// The steady state with its switches (thermostats) in states consistent with it: a switch whose
/// event function changes sign between the guess and the solution is flipped and the state solved
/// again. A switch that has to flip back has no consistent state: it cycles, with no steady state.
SolverStats steady_with_switches(Network& net, std::vector<double>& T, const SolverOptions& o) {
  const int nev = net.event_count();
  if (nev == 0) return solve_steady(net, T, 0.0, o);
  net.init_events(0.0, T.data());
  const auto n = static_cast<std::size_t>(nev);
  std::vector<double> g_guess(n), g_solution(n);
  std::vector<int> crossed(n), flips(n, 0);
  for (;;) {
    net.events(0.0, T.data(), g_guess.data());
    SolverStats stats = solve_steady(net, T, 0.0, o);
    net.events(0.0, T.data(), g_solution.data());
    if (!events_crossed(g_guess, g_solution, crossed)) return stats;
    for (std::size_t k = 0; k < n; ++k)
      if (crossed[k] != 0 && ++flips[k] > 1)
        throw SolverError(
            "there is no steady state: a thermostat (switch) cycles: heating, its sensed "
            "temperature settles above its switch-off point; off, below its switch-on point. "
            "Simulate the transient instead",
            "steady", 0, 0.0, {});
    if (!net.apply_events(0.0, T.data(), crossed)) return stats;
  }
}

/// `initial = data`: the nodes without a T0 start at the steady state at t = 0 around those that
/// have one (measured nodes start at their first measured value), which are held there.
void settle_nodes_without_start(Network& net, std::vector<double>& T, const SolverOptions& o,
                                SolverStats* stats) {
  const lang::NetworkSpec& spec = net.spec();
  lang::NetworkSpec held = spec;
  bool any_free = false;
  for (auto& n : held.nodes) {
    if (n.boundary) continue;
    if (n.T0) {
      n.boundary = true;
      n.T = lang::Signal::of(*n.T0);
    } else {
      any_free = true;
    }
  }
  if (!any_free) return;
  Network partial(std::move(held));
  std::vector<double> x = partial.initial_state();
  SolverStats s = steady_with_switches(partial, x, o);
  if (stats) *stats = s;
  std::vector<int> unknown_of(spec.nodes.size(), -1);
  for (std::size_t u = 0; u < net.unknown_nodes().size(); ++u)
    unknown_of[static_cast<std::size_t>(net.unknown_nodes()[u])] = static_cast<int>(u);
  for (std::size_t u = 0; u < partial.unknown_nodes().size(); ++u)
    T[static_cast<std::size_t>(unknown_of[static_cast<std::size_t>(partial.unknown_nodes()[u])])] =
        x[u];
  T.resize(static_cast<std::size_t>(net.temperature_count()));
  net.start_states(T);
}

} // namespace

std::vector<double> start_state(Network& net, const SolverOptions& solver, SolverStats* stats) {
  std::vector<double> T = net.initial_state();
  if (net.spec().settings.initial_data) {
    settle_nodes_without_start(net, T, solver, stats);
    if (net.event_count() > 0) net.init_events(0.0, T.data());
  } else if (net.spec().settings.initial_steady) {
    SolverStats s = steady_with_switches(net, T, solver);
    if (stats) *stats = s;
  } else if (net.event_count() > 0) {
    net.init_events(0.0, T.data());
  }
  return T;
}

SolverStats simulate(Network& net, const SimulationOptions& opt, const RowCallback& row,
                     EnergyTotals* energy) {
  const auto& settings = net.spec().settings;
  const std::size_t nodes = net.spec().nodes.size();
  const std::vector<int> sensors = opt.sensors ? net.sensor_elements() : std::vector<int>{};
  std::vector<double> all(nodes + sensors.size());
  auto record = [&](double t, const std::vector<double>& x) {
    net.expand(t, x.data(), all.data());
    for (std::size_t k = 0; k < sensors.size(); ++k)
      all[nodes + k] = net.sensor_reading(static_cast<std::size_t>(sensors[k]), t, x.data());
    row(t, all);
  };
  SolverStats steady;
  if (opt.steady) {
    std::vector<double> T = net.initial_state();
    steady = steady_with_switches(net, T, opt.solver);
    record(0.0, T);
    return steady;
  }
  std::vector<double> T = start_state(net, opt.solver, &steady);
  std::optional<double> duration = opt.duration ? opt.duration : settings.duration;
  if (!duration)
    throw std::invalid_argument(
        fmt::format("case '{}' has no duration; give one with --duration", settings.name));
  if (!(*duration > 0)) throw std::invalid_argument("the duration must be positive");
  std::vector<double> times;
  if (!opt.output && !settings.output_times.empty()) {
    // Listed times (`output = 0, 100, 250`) are written exactly, and only them.
    times = settings.output_times;
    if (times.back() > *duration)
      throw std::invalid_argument(
          fmt::format("output time {:g} s of case '{}' lies after the end of the run ({:g} s)",
                      times.back(), settings.name, *duration));
  } else {
    double interval = opt.output.value_or(settings.output.value_or(*duration / 1000.0));
    if (!(interval > 0)) throw std::invalid_argument("the output interval must be positive");
    if (*duration / interval > 1e7)
      throw std::invalid_argument(fmt::format(
          "{:g} output rows requested; use a longer output interval", *duration / interval));
    times = output_times(*duration, interval);
  }
  SolverStats s =
      energy ? integrate_with_energy(net, T, 0.0, *duration, times, record, opt.solver, *energy)
             : integrate(net, T, 0.0, *duration, times, record, opt.solver);
  if (settings.initial_steady) s.steps += steady.steps;
  return s;
}

SimulationResult simulate(Network& net, const SimulationOptions& opt) {
  SimulationResult r;
  for (const auto& n : net.spec().nodes)
    r.names.push_back(n.name);
  if (opt.sensors) // their readings follow the nodes in every row
    for (int e : net.sensor_elements())
      r.names.push_back(net.spec().elements[static_cast<std::size_t>(e)].name);
  r.stats = simulate(net, opt, [&r](double t, const std::vector<double>& temps) {
    r.times.push_back(t);
    r.temps.push_back(temps);
  });
  return r;
}

} // namespace thermnet
