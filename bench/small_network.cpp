// In-process benchmark of a small network: loads bench/models/net24.tnet (or argv[1]) once, then
// times `Network` construction + `thermnet::simulate` of its 10,000 s transient, repeated.
//
// Usage: thermnet_bench_small [MODEL.tnet] [REPETITIONS=1000] [TOLERANCE (rtol = atol)]
// Without TOLERANCE it runs at matched accuracy, as bench/run.py does: the loosest tolerance of
// the ladder 1e-4, 1e-5, ... whose final temperatures are all within 0.01 K of a run at 1e-10;
// then it also times thermnet's default (1e-6). Prints the mean, median and minimum time per run
// in ms (Network build included), the solver stats of one run and its final temperatures in K.
#include "kernel/core/element_registry.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"
#include "lang/source.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
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
  auto model = lang::Model::load(path, thermnet::element_catalog(), sources, diags);
  if (!model || diags.error_count() > 0) {
    std::fprintf(stderr, "cannot load %s (%zu errors)\n", path.c_str(), diags.error_count());
    return 1;
  }
  const lang::NetworkSpec spec = model->instantiate("");

  SimulationOptions opts;
  opts.duration = 10000.0; // the 10,000 s transient (also the case's duration)
  opts.output = 10000.0;   // only the initial and final samples
  const auto final_state = [&](double tol) {
    SimulationOptions o = opts;
    o.solver.rtol = o.solver.atol = tol;
    Network net(spec);
    return simulate(net, o);
  };
  // The tolerances to time: the one given, or the matched-accuracy one and the default.
  std::vector<double> tolerances;
  if (argc > 3) {
    tolerances.push_back(std::atof(argv[3]));
  } else {
    const SimulationResult ref = final_state(1e-10);
    for (double tol : {1e-4, 1e-5, 1e-6, 1e-7, 1e-8}) {
      const SimulationResult r = final_state(tol);
      double worst = 0.0;
      for (std::size_t i = 0; i < r.temps.back().size(); ++i)
        worst = std::max(worst, std::abs(r.temps.back()[i] - ref.temps.back()[i]));
      if (worst <= 0.01) {
        std::printf(
            "matched accuracy: rtol = atol = %g, final temperatures within %.2g K of 1e-10\n", tol,
            worst);
        tolerances.push_back(tol);
        break;
      }
    }
    tolerances.push_back(SolverOptions{}.rtol);
  }

  for (double tol : tolerances) {
    const SimulationResult first = final_state(tol); // warm-up run; gives the stats and state
    opts.solver.rtol = opts.solver.atol = tol;
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
    std::printf("model %s: %zu nodes (incl. boundaries), %d unknowns, %.0f s transient, %d "
                "repetitions, rtol = atol = %g\n",
                path.c_str(), first.names.size(), Network(spec).size(), first.times.back(), reps,
                tol);
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
    std::printf("target <= 0.2 ms per run: %s\n\n", mean <= 0.2 ? "met" : "NOT met");
  }
  return 0;
}
