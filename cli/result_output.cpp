#include "cli/result_output.hpp"

#include "lang/diagnostics.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <stdexcept>

namespace thermnet::cli {

namespace {
constexpr double kZeroCelsius = 273.15;
} // namespace

std::string result_csv_header(const std::vector<std::string>& names) {
  std::string out = "time";
  for (const auto& n : names)
    out += "," + n;
  return out + "\n";
}

std::string result_csv_row(double t, const std::vector<double>& temps) {
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out), "{:.10g}", t);
  for (double T : temps)
    fmt::format_to(std::back_inserter(out), ",{:.8f}", T - kZeroCelsius);
  out.push_back('\n');
  return fmt::to_string(out);
}

std::vector<std::size_t> plot_columns(const std::vector<std::string>& names,
                                      const std::vector<std::string>& nodes) {
  std::vector<std::size_t> columns;
  if (nodes.empty()) {
    for (std::size_t i = 0; i < names.size(); ++i)
      columns.push_back(i);
    return columns;
  }
  for (const auto& n : nodes) {
    auto it = std::find(names.begin(), names.end(), n);
    if (it == names.end()) {
      std::string msg = fmt::format("--nodes: the model has no node or boundary '{}'", n);
      if (auto s = lang::closest_match(n, names)) msg += fmt::format("; did you mean '{}'?", *s);
      throw std::invalid_argument(msg);
    }
    columns.push_back(static_cast<std::size_t>(it - names.begin()));
  }
  return columns;
}

std::string plot_result_svg(const SimulationResult& r, const std::string& title) {
  plot::Panel panel;
  panel.title = title;
  panel.y_label = "temperature [degC]";
  panel.x_is_time_s = true;
  for (std::size_t c = 0; c < r.names.size(); ++c) {
    plot::Series s;
    s.label = r.names[c];
    s.x = r.times;
    for (const auto& row : r.temps)
      s.y.push_back(row[c] - kZeroCelsius);
    panel.series.push_back(std::move(s));
  }
  plot::Figure fig;
  fig.panels.push_back(std::move(panel));
  return plot::render_svg(fig);
}

} // namespace thermnet::cli
