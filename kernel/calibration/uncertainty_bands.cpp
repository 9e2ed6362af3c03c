// Uncertainty bands by uniform sampling of the ranged params. Sample i is simulated by task i of
// parallel_for and stored in slot i as float deviations from the nominal run (half the memory
// of doubles, with no visible rounding: the deviations are small and exactly 0 where the params
// have no effect); the statistics are computed per output time and node from the slots in index
// order, so the bands do not depend on the number of threads.

#include "kernel/calibration/uncertainty_bands.hpp"

#include "kernel/core/network.hpp"
#include "kernel/core/parallel.hpp"
#include "kernel/core/process_group.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace thermnet {

double percentile_of_sorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return std::nan("");
  const double h = static_cast<double>(sorted.size() - 1) * q / 100.0;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[lo + 1] - sorted[lo]);
}

UncertaintyBands run_uncertainty(const lang::Model& model, const std::string& case_name,
                                 const UncertaintyOptions& o) {
  if (o.samples == 0) throw std::invalid_argument("--samples must be at least 1");
  for (double q : o.percentiles)
    if (!(q > 0.0 && q < 100.0))
      throw std::invalid_argument(fmt::format("--percentiles must be in (0, 100), got {:g}", q));
  UncertaintyBands b;
  b.samples = o.samples;
  b.percentiles = o.percentiles;
  const std::string name = model.resolve_case(case_name);
  {
    Network net(model.instantiate(name));
    b.nominal = simulate(net, o.simulation);
  }
  b.names = b.nominal.names;
  b.times = b.nominal.times;
  std::vector<lang::ParamInfo> ranged;
  for (const lang::ParamInfo& p : model.params())
    if (p.ranged()) {
      ranged.push_back(p);
      b.params.push_back(p.name);
    }

  const std::size_t nt = b.times.size(), nn = b.names.size();
  // Each process (MPI rank) simulates its share of the samples; the runs are then exchanged, so
  // every process computes the same bands from all of them.
  std::vector<std::vector<float>> runs(o.samples);
  auto pack = [&](std::size_t i) {
    return std::string(reinterpret_cast<const char*>(runs[i].data()),
                       runs[i].size() * sizeof(float));
  };
  auto unpack = [&](std::size_t i, std::string_view bytes) {
    runs[i].resize(bytes.size() / sizeof(float));
    std::memcpy(runs[i].data(), bytes.data(), runs[i].size() * sizeof(float));
  };
  auto run_sample = [&](std::size_t i) {
    lang::ParamValues values;
    for (std::size_t j = 0; j < ranged.size(); ++j)
      values[ranged[j].name] =
          *ranged[j].lo + (*ranged[j].hi - *ranged[j].lo) * uniform01(o.seed, j, i);
    try {
      Network net(model.instantiate(name, values));
      SimulationResult r = simulate(net, o.simulation);
      if (r.times.size() != nt) return;
      std::vector<float> flat(nt * nn);
      for (std::size_t k = 0; k < nt; ++k)
        for (std::size_t n = 0; n < nn; ++n)
          flat[k * nn + n] = static_cast<float>(r.temps[k][n] - b.nominal.temps[k][n]);
      runs[i] = std::move(flat);
    } catch (const std::exception&) {
      // A sample that cannot be simulated is left out and counted below.
    }
  };
  distributed_for(o.samples, o.threads, run_sample, pack, unpack);
  std::vector<std::size_t> ok;
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (!runs[i].empty()) ok.push_back(i);
  b.failed = o.samples - ok.size();
  if (ok.empty()) throw std::runtime_error("no sample could be simulated");

  // Per output time: each sample's row of that time is read in one pass (contiguous), so the
  // gather never strides across the samples' arrays (read node by node, every value was on
  // another page: 620 s of CPU instead of 19 s for 200 samples of 1,000 nodes on one thread).
  // A task holds one time's slice in floats, as the runs do.
  b.stats.assign(nn, std::vector<std::vector<double>>(nt));
  const std::size_t ns = ok.size();
  parallel_for(nt, o.threads, [&](std::size_t k) {
    // node n's deviations at [n ns, (n + 1) ns): one time's slice of the runs, transposed
    std::vector<float> at_k(nn * ns);
    for (std::size_t s = 0; s < ns; ++s) {
      const float* row = runs[ok[s]].data() + k * nn;
      for (std::size_t n = 0; n < nn; ++n)
        at_k[n * ns + s] = row[n];
    }
    std::vector<double> v(ns);
    for (std::size_t n = 0; n < nn; ++n) {
      for (std::size_t s = 0; s < ns; ++s)
        v[s] = b.nominal.temps[k][n] + static_cast<double>(at_k[n * ns + s]);
      std::sort(v.begin(), v.end());
      std::vector<double>& stats = b.stats[n][k];
      stats.push_back(v.front());
      for (double q : o.percentiles)
        stats.push_back(percentile_of_sorted(v, q));
      stats.push_back(v.back());
    }
  });
  return b;
}

} // namespace thermnet
