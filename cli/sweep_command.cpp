#include "cli/sweep_command.hpp"

#include "app/csv_writer.hpp"
#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "app/node_summary.hpp"
#include "app/option_rules.hpp"
#include "app/output_files.hpp"
#include "app/output_stream.hpp"
#include "app/param_overrides.hpp"
#include "app/result_output.hpp"
#include "cli/run_command.hpp"
#include "kernel/core/process_group.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/units.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <iterator>
#include <memory>
#include <optional>
#include <string_view>

namespace thermnet::cli {
using namespace app;
namespace {

using lang::kZeroCelsius;

struct SweepOptions {
  std::string model;
  std::string case_name;
  std::vector<std::string> axes;
  std::vector<std::string> sets;
  std::vector<std::string> nodes;
  std::string band;
  std::string duration;
  std::string output_interval;
  std::string out;
  std::string plot;
  double rtol = 1e-6;
  double atol = 1e-6;
  int threads = 0;
};

/// One grid point's result: a summary per selected node, or why its run failed.
struct PointResult {
  std::vector<NodeStats> stats;
  std::string error;
};

/// A point's result as bytes, for the processes that did not compute it (distributed_for).
std::string pack(const PointResult& r) {
  std::string out;
  append_values(out, r.stats);
  return out + r.error;
}

/// The result pack() wrote.
PointResult unpack(std::string_view in) {
  PointResult r;
  r.stats = take_values<NodeStats>(in);
  r.error = std::string(in);
  return r;
}

/// Most points a grid may have (the product of its axes' sizes): each is a run and a row.
constexpr std::size_t max_grid_points = 100'000;

/// Throws std::invalid_argument when the grid has more than max_grid_points points (checked
/// before any is made).
void check_grid_size(const std::vector<SweepAxis>& axes) {
  std::size_t points = 1;
  std::vector<std::string> sizes;
  for (const auto& a : axes) {
    const std::size_t n = std::max<std::size_t>(a.values.size(), 1);
    points = points > max_grid_points / n ? max_grid_points + 1 : points * n;
    sizes.push_back(std::to_string(a.values.size()));
  }
  if (points > max_grid_points)
    throw std::invalid_argument(fmt::format("--param: the grid has {} points, more than the {} a "
                                            "sweep runs; use fewer values",
                                            fmt::join(sizes, " x "), max_grid_points));
}

/// The grid points (every combination, the last axis fastest), as value indices per axis.
std::vector<std::vector<std::size_t>> grid(const std::vector<SweepAxis>& axes) {
  std::vector<std::vector<std::size_t>> points{{}};
  for (const auto& a : axes) {
    std::vector<std::vector<std::size_t>> next;
    for (const auto& p : points)
      for (std::size_t k = 0; k < a.values.size(); ++k) {
        next.push_back(p);
        next.back().push_back(k);
      }
    points = std::move(next);
  }
  return points;
}

std::string table(const std::vector<SweepAxis>& axes,
                  const std::vector<std::vector<std::size_t>>& points,
                  const std::vector<std::string>& nodes, bool band,
                  const std::vector<PointResult>& results) {
  fmt::memory_buffer out;
  auto put = [&](const std::string& s) { out.append(s.data(), s.data() + s.size()); };
  std::vector<std::string> head;
  for (const auto& a : axes)
    head.push_back(a.name);
  for (const auto& n : nodes) {
    for (const char* col : {"_min", "_max", "_mean"})
      head.push_back(n + col);
    if (band) head.push_back(n + "_time_outside");
  }
  head.push_back("error");
  put(csv_line(head));
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::vector<std::string> row;
    for (std::size_t a = 0; a < axes.size(); ++a)
      row.push_back(fmt::format("{:.10g}", axes[a].values[points[i][a]] - axes[a].display_offset));
    for (std::size_t c = 0; c < nodes.size(); ++c) {
      if (!results[i].error.empty()) {
        row.insert(row.end(), band ? 4 : 3, "");
        continue;
      }
      const NodeStats& s = results[i].stats[c];
      row.push_back(fmt::format("{:.6f}", s.min - kZeroCelsius));
      row.push_back(fmt::format("{:.6f}", s.max - kZeroCelsius));
      row.push_back(fmt::format("{:.6f}", s.mean - kZeroCelsius));
      if (band) row.push_back(fmt::format("{:.10g}", s.outside));
    }
    row.push_back(results[i].error);
    put(csv_line(row));
  }
  return fmt::to_string(out);
}

/// Min, mean and max of each node against the first param (one curve per value of the others
/// would crowd the plot: the other params are held at their first value).
std::string plot_svg(const std::string& title, const std::vector<SweepAxis>& axes,
                     const std::vector<std::vector<std::size_t>>& points,
                     const std::vector<std::string>& nodes,
                     const std::vector<PointResult>& results) {
  plot::Panel panel;
  panel.title = title;
  panel.x_label = axes.front().name;
  panel.y_label = "temperature [degC]";
  for (std::size_t c = 0; c < nodes.size(); ++c)
    for (int which = 0; which < 3; ++which) {
      plot::Series s;
      s.label = nodes[c] + (which == 0 ? " min" : which == 1 ? " mean" : " max");
      for (std::size_t i = 0; i < points.size(); ++i) {
        bool others_first = true;
        for (std::size_t a = 1; a < axes.size(); ++a)
          others_first = others_first && points[i][a] == 0;
        if (!others_first || !results[i].error.empty()) continue;
        const NodeStats& st = results[i].stats[c];
        s.x.push_back(axes.front().values[points[i][0]] - axes.front().display_offset);
        s.y.push_back((which == 0 ? st.min : which == 1 ? st.mean : st.max) - kZeroCelsius);
      }
      panel.series.push_back(std::move(s));
    }
  plot::Figure fig;
  fig.panels.push_back(std::move(panel));
  return plot::render_svg(fig);
}

int run_sweep(const SweepOptions& o, lang::SourceManager& sources) {
  int status = exit_ok;
  auto model = load_checked_model(o.model, sources, status, o.sets);
  if (!model) return status;
  check_outputs({{"-o", o.out}, {"--plot", o.plot}}, model_inputs(*model));
  std::vector<SweepAxis> axes;
  std::vector<std::string> given; // what --set gives is not swept, and no axis is given twice
  for (const auto& s : o.sets)
    given.push_back(resolve_target(*model, s.substr(0, s.find('=')), "--set").name);
  for (const auto& a : o.axes) {
    axes.push_back(parse_sweep_axis(*model, a));
    refuse_repeated(given, axes.back().target, "--param " + a);
  }
  check_grid_size(axes);
  const auto points = grid(axes);
  SimulationOptions sim;
  if (!o.duration.empty()) sim.duration = parse_time(o.duration);
  if (!o.output_interval.empty()) sim.output = parse_time(o.output_interval);
  sim.solver.rtol = o.rtol;
  sim.solver.atol = o.atol;
  const std::optional<Band> band =
      o.band.empty() ? std::optional<Band>{} : std::optional<Band>{parse_band(o.band)};
  // The selection is checked once, on the nominal network, before the grid runs.
  const lang::NetworkSpec nominal = model->instantiate(o.case_name);
  std::vector<std::string> names;
  for (const auto& n : nominal.nodes)
    names.push_back(n.name);
  const std::vector<std::size_t> columns = plot_columns(names, o.nodes);
  std::vector<std::string> selected;
  for (std::size_t c : columns)
    selected.push_back(names[c]);

  // Each process (MPI rank) runs its share of the grid; the results are then exchanged, and rank 0
  // writes the one table (docs/cluster.md).
  std::vector<PointResult> results(points.size());
  auto run_point = [&](std::size_t i) {
    // A point is the model with --set values and the axes' values set the same way.
    lang::Overrides values = model->overrides();
    for (std::size_t a = 0; a < axes.size(); ++a)
      add_override(values, axes[a].target, axes[a].values[points[i][a]], "--param " + axes[a].name);
    try {
      Network net(model->instantiate(o.case_name, {}, values));
      NodeSummary summary(names, columns, band);
      simulate(net, sim, [&](double t, const std::vector<double>& T) { summary.add(t, T); });
      results[i].stats = summary.results();
    } catch (const std::exception& e) {
      results[i].error = e.what();
    }
  };
  distributed_for(
      points.size(), o.threads, run_point, [&](std::size_t i) { return pack(results[i]); },
      [&](std::size_t i, std::string_view bytes) { results[i] = unpack(bytes); });
  std::size_t failed = 0;
  for (const auto& r : results)
    failed += r.error.empty() ? 0 : 1;
  std::cerr << fmt::format("thermnet sweep: {} runs, {} failed\n", points.size(), failed);
  auto csv = open_output(o.out);
  csv->write(table(axes, points, selected, band.has_value(), results));
  std::unique_ptr<OutputStream> svg;
  if (!o.plot.empty()) {
    svg = std::make_unique<OutputStream>(o.plot);
    svg->write(plot_svg(fmt::format("{} — case {}", model->name(), nominal.settings.name), axes,
                        points, selected, results));
  }
  commit({csv.get(), svg.get()});
  return failed == points.size() ? exit_failure : exit_ok;
}

} // namespace

void add_sweep_command(CLI::App& app, int& status) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sweep", "Run a case over a grid of param values: one summary row per grid point");
  cmd->add_option("MODEL", o->model, "model file (.tnet)")->required();
  cmd->add_option("--param", o->axes,
                  "swept param or key: NAME=LO..HI:N (N values) or NAME=V1,V2,... (NAME a param "
                  "or NAME.KEY of a node, boundary or element, values as --set); repeat for a "
                  "grid")
      ->required();
  cmd->add_option("--case", o->case_name, "case to run (default: the only case, or 'default')");
  add_set_option(cmd, o->sets, "; the same for every point");
  cmd->add_option("--nodes", o->nodes, "nodes summarised: names or globs (default: all)")
      ->delimiter(',');
  cmd->add_option("--band", o->band, "LO..HI in degC: adds each node's time outside it, s");
  cmd->add_option("--duration", o->duration, "simulated time (overrides the case)");
  cmd->add_option("--output", o->output_interval, "output interval (overrides the case)");
  cmd->add_option("-o,--out", o->out, "CSV table (default: standard output)")
      ->check(output_file_validator());
  cmd->add_option("--plot", o->plot, "SVG of each node's min, mean and max against the first param")
      ->check(output_file_validator());
  cmd->add_option("--rtol", o->rtol, "relative tolerance")
      ->check(rule_validator(relative_tolerance_rule, "NUMBER"));
  cmd->add_option("--atol", o->atol, "absolute tolerance, K")
      ->check(rule_validator(absolute_tolerance_rule, "NUMBER"));
  cmd->add_option("--threads", o->threads, "worker threads (0: all cores); same table for any")
      ->check(rule_validator(non_negative_whole_rule, "INT"));
  cmd->callback([o, &status] {
    status = run_command(
        "thermnet sweep", [&](lang::SourceManager& sources) { return run_sweep(*o, sources); },
        exit_usage);
  });
}

} // namespace thermnet::cli
