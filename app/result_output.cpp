#include "app/result_output.hpp"

#include "app/csv_writer.hpp"
#include "lang/diagnostics.hpp"
#include "lang/name_list.hpp"
#include "lang/units.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fnmatch.h>
#include <iterator>
#include <stdexcept>
#include <string_view>

namespace thermnet::app {

namespace {
using lang::kZeroCelsius;
} // namespace

std::string result_csv_header(const std::vector<std::string>& names) {
  fmt::memory_buffer out;
  out.append(std::string_view("time"));
  for (const auto& n : names) {
    out.push_back(',');
    append_csv_field(out, n);
  }
  out.push_back('\n');
  return fmt::to_string(out);
}

std::string result_csv_row(double t, const std::vector<double>& temps, bool kelvin) {
  const double offset = kelvin ? 0.0 : kZeroCelsius;
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out), "{:.10g}", t);
  for (double T : temps)
    fmt::format_to(std::back_inserter(out), ",{:.8f}", T - offset);
  out.push_back('\n');
  return fmt::to_string(out);
}

std::vector<std::size_t> select_names(const std::vector<std::string>& names,
                                      const std::vector<std::string>& patterns,
                                      const std::string& option, const std::string& what) {
  std::vector<std::size_t> selected;
  if (patterns.empty()) {
    for (std::size_t i = 0; i < names.size(); ++i)
      selected.push_back(i);
    return selected;
  }
  std::vector<char> taken(names.size(), 0);
  for (const auto& p : lang::join_bracketed(patterns)) {
    // A name is taken literally first: an indexed name such as p[3,7] is also a valid glob.
    const bool literal = std::find(names.begin(), names.end(), p) != names.end();
    bool any = false;
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (literal ? names[i] != p : ::fnmatch(p.c_str(), names[i].c_str(), 0) != 0) continue;
      any = true;
      if (!taken[i]) selected.push_back(i);
      taken[i] = 1;
    }
    if (any) continue;
    std::string msg = fmt::format("{}: the model has no {} '{}'", option, what, p);
    if (auto s = lang::closest_match(p, names)) msg += fmt::format("; did you mean '{}'?", *s);
    throw std::invalid_argument(msg);
  }
  return selected;
}

std::vector<std::size_t> plot_columns(const std::vector<std::string>& names,
                                      const std::vector<std::string>& nodes) {
  return select_names(names, nodes, "--nodes", "node or boundary");
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

} // namespace thermnet::app
