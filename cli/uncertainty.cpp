// Uncertainty bands by uniform sampling of the ranged params. Sample i is simulated by task i of
// parallel_for and stored in slot i as float deviations from the nominal run (half the memory
// of doubles, with no visible rounding: the deviations are small and exactly 0 where the params
// have no effect); the
// statistics are computed per node from the slots in index order, so the bands do not depend on
// the number of threads.

#include "cli/uncertainty.hpp"

#include "cli/csv_writer.hpp"
#include "cli/result_output.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/parallel.hpp"
#include "kernel/core/process_group.hpp"
#include "lang/units.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <stdexcept>

namespace thermnet::cli {
namespace {

using lang::kZeroCelsius;

} // namespace

double percentile_of_sorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return std::nan("");
  const double h = static_cast<double>(sorted.size() - 1) * q / 100.0;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[lo + 1] - sorted[lo]);
}

std::string percentile_label(double q) {
  return fmt::format("p{:g}", q);
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

  b.stats.assign(nn, std::vector<std::vector<double>>(nt));
  parallel_for(nn, o.threads, [&](std::size_t n) {
    std::vector<double> v(ok.size());
    for (std::size_t k = 0; k < nt; ++k) {
      for (std::size_t s = 0; s < ok.size(); ++s)
        v[s] = b.nominal.temps[k][n] + static_cast<double>(runs[ok[s]][k * nn + n]);
      std::sort(v.begin(), v.end());
      std::vector<double>& row = b.stats[n][k];
      row.push_back(v.front());
      for (double q : o.percentiles)
        row.push_back(percentile_of_sorted(v, q));
      row.push_back(v.back());
    }
  });
  return b;
}

std::string format_bands_csv(const UncertaintyBands& b) {
  fmt::memory_buffer out;
  out.append(std::string_view("time"));
  auto column = [&](const std::string& name) {
    out.push_back(',');
    append_csv_field(out, name);
  };
  for (const auto& n : b.names) {
    column(n + "_min");
    for (double q : b.percentiles)
      column(n + "_" + percentile_label(q));
    column(n + "_max");
  }
  out.push_back('\n');
  for (std::size_t k = 0; k < b.times.size(); ++k) {
    fmt::format_to(std::back_inserter(out), "{:.10g}", b.times[k]);
    for (std::size_t n = 0; n < b.names.size(); ++n)
      for (double T : b.stats[n][k])
        fmt::format_to(std::back_inserter(out), ",{:.6f}", T - kZeroCelsius);
    out.push_back('\n');
  }
  return fmt::to_string(out);
}

std::string plot_bands_svg(const UncertaintyBands& b, const std::vector<std::string>& nodes,
                           const std::string& title) {
  const std::vector<std::size_t> columns = plot_columns(b.names, nodes);
  // The middle reported percentile (the median with the defaults) is drawn as the line.
  const std::size_t mid = b.percentiles.empty() ? 0 : 1 + b.percentiles.size() / 2;
  const std::string mid_label =
      b.percentiles.empty() ? "min" : percentile_label(b.percentiles[mid - 1]);
  plot::Panel panel;
  panel.title = title;
  panel.y_label = "temperature [degC]";
  panel.x_is_time_s = true;
  int color = 0;
  for (std::size_t c : columns) {
    plot::Band band;
    band.label = b.names[c] + " min..max";
    band.x = b.times;
    plot::Series line, nominal;
    line.label = b.names[c] + " " + mid_label;
    line.x = nominal.x = b.times;
    nominal.label = b.names[c] + " nominal";
    nominal.style = plot::LineStyle::dashed;
    for (std::size_t k = 0; k < b.times.size(); ++k) {
      const auto& row = b.stats[c][k];
      band.lo.push_back(row.front() - kZeroCelsius);
      band.hi.push_back(row.back() - kZeroCelsius);
      line.y.push_back(row[mid] - kZeroCelsius);
      nominal.y.push_back(b.nominal.temps[k][c] - kZeroCelsius);
    }
    band.color = line.color = nominal.color = color++;
    panel.bands.push_back(std::move(band));
    panel.series.push_back(std::move(line));
    panel.series.push_back(std::move(nominal));
  }
  plot::Figure fig;
  fig.panels.push_back(std::move(panel));
  return plot::render_svg(fig);
}

} // namespace thermnet::cli
