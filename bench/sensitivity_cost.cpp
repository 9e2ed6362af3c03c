// In-process benchmark of forward sensitivities: what one case simulation costs plain, and with the
// sensitivities of its first 1, 2, ... ranged params (CVODES, kernel/core/case_sensitivities.hpp),
// against the forward differences they replace (one more simulation per param).
//
// Usage: thermnet_bench_sensitivity MODEL.tnet [CASE] [REPETITIONS=20] [TOLERANCE=1e-7]
// The case (default: the first with data, else the first) runs from 0 to its duration with an
// output at every output time of the case; the solver is the diagnosis's (rtol = atol =
// TOLERANCE, dense LU up to 64 unknowns, KLU above). Prints the CPU time per run (ms, the median
// of the repetitions, one thread) of the elaboration, the plain simulation and each sensitivity
// run, and the largest difference between the plain and the sensitivity run's temperatures; and
// the elaboration of a network with one param moved, in full and from the case's record (as the
// sensitivity runs make their moved networks).
#include "kernel/core/case_sensitivities.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/diagnostics.hpp"
#include "lang/elaborator.hpp"
#include "lang/model.hpp"
#include "lang/source.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace thermnet;

/// CPU time of one call of f, ms.
double cpu_ms(const std::function<void()>& f) {
  timespec a{}, b{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &a);
  f();
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &b);
  return 1e3 * static_cast<double>(b.tv_sec - a.tv_sec) +
         1e-6 * static_cast<double>(b.tv_nsec - a.tv_nsec);
}

double median(std::vector<double> t) {
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

/// Median CPU time of `reps` calls of f, ms.
double median_ms(int reps, const std::function<void()>& f) {
  std::vector<double> t;
  for (int i = 0; i < reps; ++i)
    t.push_back(cpu_ms(f));
  return median(t);
}

} // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MODEL.tnet [CASE] [REPETITIONS=20] [TOLERANCE=1e-7]\n",
                 argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const int reps = argc > 3 ? std::max(1, std::atoi(argv[3])) : 20;
  SolverOptions solver;
  solver.rtol = solver.atol = argc > 4 ? std::atof(argv[4]) : 1e-7;
  solver.dense_threshold = 64;

  lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  auto model = lang::Model::load(path, element_catalog(), sources, diags);
  if (!model || diags.error_count() > 0) {
    std::fprintf(stderr, "cannot load %s (%zu errors)\n", path.c_str(), diags.error_count());
    return 1;
  }
  std::string case_name = argc > 2 ? argv[2] : "";
  if (case_name.empty()) {
    const auto names = model->run_case_names();
    for (const auto& n : names)
      if (case_name.empty() && !model->instantiate(n).settings.data_path.empty()) case_name = n;
    if (case_name.empty() && !names.empty()) case_name = names.front();
  }
  const lang::NetworkSpec spec = model->instantiate(case_name);
  const auto& st = spec.settings;
  std::vector<double> times = !st.output_times.empty()
                                  ? st.output_times
                                  : output_times(st.duration.value_or(3600.0),
                                                 st.output.value_or(st.duration.value_or(3600.0)));
  std::vector<lang::ParamInfo> ranged;
  for (auto& p : model->params())
    if (p.ranged()) ranged.push_back(p);
  std::vector<int> nodes;
  for (std::size_t i = 0; i < spec.nodes.size(); ++i)
    if (!spec.nodes[i].boundary) nodes.push_back(static_cast<int>(i));

  // As the diagnosis does: each moved network elaborated from the record of the case's.
  std::shared_ptr<const lang::ElaborationRecord> record;
  (void)model->instantiate_recorded(case_name, {}, record);
  const auto moved_values = [&](std::size_t j, MovedSpec* m = nullptr) {
    const double scale =
        std::max(std::abs(ranged[j].value), 1e-3 * (*ranged[j].hi - *ranged[j].lo));
    if (m) {
      m->scale = scale;
      m->step = 1e-7 * scale;
    }
    return lang::ParamValues{{ranged[j].name, ranged[j].value + 1e-7 * scale}};
  };
  const auto moved_network = [&](std::size_t j, MovedSpec* m = nullptr) {
    return record ? model->instantiate_near(*record, moved_values(j, m))
                  : model->instantiate(case_name, moved_values(j, m));
  };
  const auto moved_specs = [&](std::size_t count) {
    std::vector<MovedSpec> moved;
    for (std::size_t j = 0; j < count; ++j) {
      MovedSpec m;
      m.spec = moved_network(j, &m);
      moved.push_back(std::move(m));
    }
    return moved;
  };
  std::vector<std::vector<double>> plain;
  const auto run_plain_spec = [&](const lang::NetworkSpec& sp) {
    Network net(sp);
    std::vector<double> T = start_state(net, solver);
    std::vector<double> all(spec.nodes.size());
    plain.clear();
    integrate(
        net, T, 0.0, times.back(), times,
        [&](double t, const std::vector<double>& x) {
          net.expand(t, x.data(), all.data());
          std::vector<double> row;
          for (int i : nodes)
            row.push_back(all[static_cast<std::size_t>(i)]);
          plain.push_back(std::move(row));
        },
        solver);
  };
  const auto run_plain = [&] { run_plain_spec(spec); };
  std::printf("%s, case %s: %zu nodes, %zu elements, %zu output times, %zu ranged params; "
              "rtol = atol = %g; CPU ms per run (median of %d)\n",
              path.c_str(), case_name.c_str(), spec.nodes.size(), spec.elements.size(),
              times.size(), ranged.size(), solver.rtol, reps);
  const double elaborate = median_ms(reps, [&] { (void)model->instantiate(case_name); });
  const double base = median_ms(reps, run_plain);
  std::printf("  elaboration (Model::instantiate): %.3f ms\n", elaborate);
  if (record && !ranged.empty()) {
    // A network with one param moved (each in turn), elaborated in full and from the case's
    // record, the two alternating.
    std::vector<double> full, near, recorded;
    for (int i = 0; i < reps; ++i) {
      full.push_back(cpu_ms([&] {
        for (std::size_t j = 0; j < ranged.size(); ++j)
          (void)model->instantiate(case_name, moved_values(j));
      }));
      near.push_back(cpu_ms([&] {
        for (std::size_t j = 0; j < ranged.size(); ++j)
          (void)moved_network(j);
      }));
      recorded.push_back(cpu_ms([&] {
        std::shared_ptr<const lang::ElaborationRecord> r;
        (void)model->instantiate_recorded(case_name, {}, r);
      }));
    }
    const double n = static_cast<double>(ranged.size());
    std::printf("  elaboration with its record (Model::instantiate_recorded): %.3f ms; one param "
                "moved (mean over the %zu ranged params): %.3f ms in full, %.3f ms from the record "
                "(Model::instantiate_near)\n",
                median(recorded), ranged.size(), median(full) / n, median(near) / n);
  }
  {
    Network net(spec);
    std::vector<double> T = start_state(net, solver);
    const SolverStats s = integrate(net, T, 0.0, times.back(), times, nullptr, solver);
    std::printf("  plain simulation: %.3f ms; %ld steps, %ld Newton iterations, %ld linear setups, "
                "%ld error test failures\n",
                base, s.steps, s.nonlinear_iters, s.linear_setups, s.error_test_fails);
  }
  for (std::size_t k = 1; k <= ranged.size(); ++k) {
    std::optional<NodeSensitivities> out;
    std::string why;
    const double ms = median_ms(reps, [&] {
      out = simulate_sensitivities(spec, moved_specs(k), times, nodes, solver, &why);
    });
    if (!out) {
      std::printf("  sensitivities unavailable: %s\n", why.c_str());
      break;
    }
    double diff = 0.0;
    for (std::size_t t = 0; t < plain.size(); ++t)
      for (std::size_t i = 0; i < nodes.size(); ++i)
        diff = std::max(diff, std::abs(plain[t][i] - out->T[t][i]));
    // The last parameter's sensitivities against central differences of two plain runs.
    const lang::ParamInfo& q = ranged[k - 1];
    const double scale = std::max(std::abs(q.value), 1e-3 * (*q.hi - *q.lo)), h = 1e-4 * scale;
    run_plain_spec(model->instantiate(case_name, {{q.name, q.value + h}}));
    const auto up = plain;
    run_plain_spec(model->instantiate(case_name, {{q.name, q.value - h}}));
    double worst = 0.0, size = 0.0;
    bool finite = true;
    for (std::size_t t = 0; t < plain.size(); ++t)
      for (std::size_t i = 0; i < nodes.size(); ++i) {
        const double fd = (up[t][i] - plain[t][i]) / (2 * h), s = out->dT[k - 1][t][i];
        finite = finite && std::isfinite(s);
        worst = std::max(worst, std::abs(fd - s) * scale);
        size = std::max(size, std::abs(fd) * scale);
      }
    std::printf("  d T / d %s times %g: largest %.3g K; sensitivities %s, largest difference from "
                "central differences %.2g K\n",
                q.name.c_str(), scale, size, finite ? "finite" : "NOT FINITE", worst);
    run_plain();
    const SolverStats& s = out->stats;
    std::printf("  with %zu sensitivit%s (elaborations included): %.3f ms = %.2f plain runs "
                "(forward differences: %zu); max |T - T_plain| %.2g K; %ld steps, %ld Newton "
                "iterations, %ld error test failures; sensitivities: %ld right-hand sides, %ld "
                "corrector iterations, %ld failures\n",
                k, k == 1 ? "y" : "ies", ms, ms / base, k + 1, diff, s.steps, s.nonlinear_iters,
                s.error_test_fails, s.sens_rhs_evals, s.sens_nonlinear_iters,
                s.sens_nonlinear_fails);
  }
  return 0;
}
