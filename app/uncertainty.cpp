// The uncertainty bands' reports (the sampling and statistics:
// kernel/calibration/uncertainty_bands): CSV text and an SVG plot.

#include "app/uncertainty.hpp"

#include "app/csv_writer.hpp"
#include "app/result_output.hpp"
#include "lang/units.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>

#include <iterator>

namespace thermnet::app {
namespace {

using lang::kZeroCelsius;

} // namespace

std::string percentile_label(double q) {
  return fmt::format("p{:g}", q);
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

} // namespace thermnet::app
