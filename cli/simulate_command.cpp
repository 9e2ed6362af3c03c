#include "cli/simulate_command.hpp"

#include "cli/atomic_file.hpp"
#include "cli/exit_status.hpp"
#include "cli/model_loading.hpp"
#include "cli/result_output.hpp"
#include "cli/run_command.hpp"
#include "cli/uncertainty.hpp"
#include "kernel/core/simulation.hpp"

#include <fmt/format.h>

#include <chrono>

#include <iostream>
#include <memory>

namespace thermnet::cli {
namespace {

struct SimulateOptions {
  std::string model;
  std::string case_name;
  bool steady = false;
  std::string duration;
  std::string output_interval;
  std::string out;
  std::string plot;
  std::vector<std::string> nodes;
  bool stats = false;
  double rtol = 1e-6;
  double atol = 1e-6;
  std::string linear_solver = "auto";
  std::size_t samples = 0; // > 0: uncertainty bands (cli/uncertainty.hpp)
  std::uint64_t seed = 1;
  std::vector<double> percentiles{5, 50, 95};
  int threads = 0;
};

/// Writes the CSV (to standard output without -o), then the plot if there is one.
void write_outputs(const SimulateOptions& o, const std::string& csv, const std::string& svg) {
  if (o.out.empty())
    std::cout << csv;
  else
    write_file_atomically(o.out, csv);
  if (!svg.empty()) write_file_atomically(o.plot, svg);
}

/// `--samples N`: bands over N draws of the ranged params instead of one run.
void run_samples(const lang::Model& model, const SimulateOptions& o, const SimulationOptions& sim) {
  UncertaintyOptions u;
  u.samples = o.samples;
  u.seed = o.seed;
  u.percentiles = o.percentiles;
  u.threads = o.threads;
  u.simulation = sim;
  UncertaintyBands b = run_uncertainty(model, o.case_name, u);
  std::cerr << fmt::format("thermnet simulate: {} samples of {} ranged params, {} failed\n",
                           b.samples, b.params.size(), b.failed);
  std::string svg;
  if (!o.plot.empty())
    svg = plot_bands_svg(b, o.nodes,
                         fmt::format("{} — case {}, {} samples", model.name(),
                                     model.resolve_case(o.case_name), b.samples));
  write_outputs(o, format_bands_csv(b), svg);
}

LinearSolverKind solver_kind(const std::string& s) {
  if (s == "dense") return LinearSolverKind::dense;
  if (s == "klu") return LinearSolverKind::klu;
  if (s == "krylov") return LinearSolverKind::krylov;
  return LinearSolverKind::automatic;
}

void print_stats(const SolverStats& s, double wall) {
  std::cerr << fmt::format(
      "thermnet: {} with {} linear solver: {} steps, {} rhs evaluations, {} Jacobians, "
      "{} linear setups, {} Newton iterations ({} failed), {} linear iterations, "
      "{} preconditioner setups, {} error test failures, {} events, {} restarts, {:.3f} s wall\n",
      s.integrator, s.linear_solver, s.steps, s.rhs_evals, s.jac_evals, s.linear_setups,
      s.nonlinear_iters, s.nonlinear_fails, s.linear_iters, s.prec_setups, s.error_test_fails,
      s.events, s.restarts, wall);
}

int run_simulate(const SimulateOptions& o, lang::SourceManager& sources) {
  int status = exit_ok;
  auto model = load_checked_model(o.model, sources, status);
  if (!model) return status;
  SimulationOptions sim;
  if (!o.duration.empty()) sim.duration = parse_time(o.duration);
  if (!o.output_interval.empty()) sim.output = parse_time(o.output_interval);
  sim.steady = o.steady;
  sim.solver.rtol = o.rtol;
  sim.solver.atol = o.atol;
  sim.solver.linear_solver = solver_kind(o.linear_solver);
  if (o.samples > 0) {
    run_samples(*model, o, sim);
    return exit_ok;
  }
  Network net(model->take_network(o.case_name));
  auto start = std::chrono::steady_clock::now();
  SimulationResult r = simulate(net, sim);
  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (o.stats) print_stats(r.stats, wall);
  std::string svg;
  if (!o.plot.empty())
    svg = plot_result_svg(r, o.nodes,
                          fmt::format("{} — case {}", model->name(), net.spec().settings.name));
  write_outputs(o, format_result_csv(r), svg);
  return exit_ok;
}

} // namespace

void add_simulate_command(CLI::App& app, int& status) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a case: temperatures over time as CSV");
  cmd->add_option("MODEL", o->model, "model file (.tnet)")->required();
  cmd->add_option("--case", o->case_name, "case to run (default: the only case, or 'default')");
  cmd->add_flag("--steady", o->steady,
                "solve the steady state (inputs at t = 0), one row at time 0");
  cmd->add_option("--duration", o->duration,
                  "simulated time, e.g. 2500, 3h, 45min (overrides the case)");
  cmd->add_option("--output", o->output_interval,
                  "output interval, e.g. 10, 1min (default: duration/1000)");
  cmd->add_option("-o,--out", o->out, "CSV output file (default: standard output)");
  cmd->add_option("--plot", o->plot, "SVG plot of node temperatures against time");
  cmd->add_option("--nodes", o->nodes, "nodes to plot (comma-separated; default: all)")
      ->delimiter(',');
  cmd->add_flag("--stats", o->stats, "print solver statistics to standard error");
  cmd->add_option("--rtol", o->rtol, "relative tolerance")->check(CLI::Range(1e-12, 1e-1));
  cmd->add_option("--atol", o->atol, "absolute tolerance, K")->check(CLI::Range(1e-12, 10.0));
  cmd->add_option("--linear-solver", o->linear_solver, "linear solver")
      ->check(CLI::IsMember({"auto", "dense", "klu", "krylov"}));
  cmd->add_option("--samples", o->samples,
                  "uncertainty bands: draw the ranged params uniformly N times; the CSV gets "
                  "NODE_min, NODE_pQ..., NODE_max columns");
  cmd->add_option("--seed", o->seed, "random seed of --samples (same seed, same bands)");
  cmd->add_option("--percentiles", o->percentiles, "percentiles of --samples (default 5,50,95)")
      ->delimiter(',');
  cmd->add_option("--threads", o->threads, "worker threads of --samples (0: all cores)")
      ->check(CLI::NonNegativeNumber);
  // Its std::invalid_argument errors come from its options (times, --nodes, --percentiles): usage.
  cmd->callback([o, &status] {
    status = run_command(
        "thermnet simulate",
        [&](lang::SourceManager& sources) { return run_simulate(*o, sources); }, exit_usage);
  });
}

} // namespace thermnet::cli
