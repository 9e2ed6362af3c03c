#include "cli/result_output.hpp"

#include "lang/diagnostics.hpp"
#include "lang/name_list.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>

#include <iterator>
#include <stdexcept>
#include <string_view>

namespace thermnet::cli {

void append_csv_field(fmt::memory_buffer& out, const std::string& name) {
  if (name.find_first_of(",\"") == std::string::npos) {
    out.append(name);
    return;
  }
  out.push_back('"');
  for (char c : name) {
    if (c == '"') out.push_back('"');
    out.push_back(c);
  }
  out.push_back('"');
}

std::string format_result_csv(const SimulationResult& r) {
  fmt::memory_buffer out;
  out.append(std::string_view("time"));
  for (const auto& n : r.names) {
    out.push_back(',');
    append_csv_field(out, n);
  }
  out.push_back('\n');
  for (std::size_t k = 0; k < r.times.size(); ++k) {
    fmt::format_to(std::back_inserter(out), "{:.10g}", r.times[k]);
    for (double T : r.temps[k])
      fmt::format_to(std::back_inserter(out), ",{:.8f}", T - 273.15);
    out.push_back('\n');
  }
  return fmt::to_string(out);
}

std::string plot_result_svg(const SimulationResult& r, const std::vector<std::string>& nodes,
                            const std::string& title) {
  std::vector<std::size_t> columns;
  if (nodes.empty()) {
    for (std::size_t i = 0; i < r.names.size(); ++i)
      columns.push_back(i);
  } else {
    for (const auto& n : lang::join_bracketed(nodes)) {
      std::size_t i = 0;
      while (i < r.names.size() && r.names[i] != n)
        ++i;
      if (i == r.names.size()) {
        std::string msg = fmt::format("--nodes: the model has no node or boundary '{}'", n);
        if (auto s = lang::closest_match(n, r.names))
          msg += fmt::format("; did you mean '{}'?", *s);
        throw std::invalid_argument(msg);
      }
      columns.push_back(i);
    }
  }
  plot::Panel panel;
  panel.title = title;
  panel.y_label = "temperature [degC]";
  panel.x_is_time_s = true;
  for (std::size_t c : columns) {
    plot::Series s;
    s.label = r.names[c];
    s.x = r.times;
    for (const auto& row : r.temps)
      s.y.push_back(row[c] - 273.15);
    panel.series.push_back(std::move(s));
  }
  plot::Figure fig;
  fig.panels.push_back(std::move(panel));
  return plot::render_svg(fig);
}

} // namespace thermnet::cli
