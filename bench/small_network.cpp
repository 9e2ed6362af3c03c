// In-process benchmark of a small network: loads bench/models/net24.tnet (or argv[1]) once, then
// times `Network` construction + `thermnet::simulate` of its 10,000 s transient, repeated.
//
// Usage: thermnet_bench_small [MODEL.tnet] [REPETITIONS=1000] [TOLERANCE=1e-6 (rtol = atol)]
// Prints the mean, median and minimum time per run in ms (Network build included), the solver
// stats of one run and its final temperatures in K (compare with a run at a tight TOLERANCE).
#include "kernel/element_registry.hpp"
#include "kernel/network.hpp"
#include "kernel/simulation.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"
#include "lang/source.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#ifndef THERMNET_BENCH_DEFAULT_MODEL
#define THERMNET_BENCH_DEFAULT_MODEL "bench/models/net24.tnet"
#endif

int main(int argc, char** argv) {
  using namespace thermnet;
  std::string path = argc > 1 ? argv[1] : THERMNET_BENCH_DEFAULT_MODEL;
  int reps = argc > 2 ? std::atoi(argv[2]) : 1000;
  if (reps < 1) reps = 1;

  lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  auto model = lang::Model::load(path, ElementRegistry::global(), sources, diags);
  if (!model || diags.error_count() > 0) {
    std::fprintf(stderr, "cannot load %s (%zu errors)\n", path.c_str(), diags.error_count());
    return 1;
  }
  const lang::NetworkSpec spec = model->instantiate("");

  SimulationOptions opts;
  opts.duration = 10000.0; // the 10,000 s transient (also the case's duration)
  opts.output = 10000.0;   // only the initial and final samples
  if (argc > 3) opts.solver.rtol = opts.solver.atol = std::atof(argv[3]); // e.g. a reference

  // warm-up run, also gives the stats and the final state
  SimulationResult first;
  int unknowns = 0;
  {
    Network net(spec);
    unknowns = net.size();
    first = simulate(net, opts);
  }
  std::vector<double> ms;
  ms.reserve(static_cast<std::size_t>(reps));
  volatile double sink = 0.0;
  for (int i = 0; i < reps; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    Network net(spec); // building the Network is part of every run
    SimulationResult r = simulate(net, opts);
    auto t1 = std::chrono::steady_clock::now();
    sink = sink + r.temps.back()[0];
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  double mean = 0.0;
  for (double x : ms)
    mean += x;
  mean /= static_cast<double>(ms.size());
  std::vector<double> sorted = ms;
  std::sort(sorted.begin(), sorted.end());
  const SolverStats& s = first.stats;
  std::printf(
      "model %s: %zu nodes (incl. boundaries), %d unknowns, %.0f s transient, %d repetitions\n",
      path.c_str(), first.names.size(), unknowns, first.times.back(), reps);
  std::printf("per run (Network build + simulate): mean %.4f ms, median %.4f ms, min %.4f ms\n",
              mean, sorted[sorted.size() / 2], sorted.front());
  std::printf("stats: %s/%s, %ld steps, %ld rhs evals, %ld Jacobians, %ld linear setups, "
              "%ld Newton iters (%ld failed), %ld error test fails, %ld restarts\n",
              s.integrator.c_str(), s.linear_solver.c_str(), s.steps, s.rhs_evals, s.jac_evals,
              s.linear_setups, s.nonlinear_iters, s.nonlinear_fails, s.error_test_fails,
              s.restarts);
  std::printf("final (K):");
  for (double v : first.temps.back())
    std::printf(" %.9f", v);
  std::printf("\n");
  std::printf("target <= 0.2 ms per run: %s\n", mean <= 0.2 ? "met" : "NOT met");
  return 0;
}
