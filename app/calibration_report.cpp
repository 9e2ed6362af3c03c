#include "app/calibration_report.hpp"

#include "lang/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet::app {

namespace {

using lang::kZeroCelsius;

/// Display width of UTF-8 text (code points; enough for the headings used here).
std::size_t width_of(const std::string& s) {
  return static_cast<std::size_t>(
      std::count_if(s.begin(), s.end(), [](char c) { return (c & 0xC0) != 0x80; }));
}

std::string pad_left(const std::string& s, std::size_t w) {
  const std::size_t n = width_of(s);
  return n >= w ? s : std::string(w - n, ' ') + s;
}

std::string number(double v) {
  return fmt::format("{:.6g}", v);
}

} // namespace

void note_undefined_r2(OptimizerResult& r) {
  if (r.found && std::isnan(r.r2))
    r.notes.push_back("R² is undefined: every measured point has the same value, so there is no "
                      "spread for the fit to explain (judge it by the RMSE)");
}

std::string param_heading(const lang::ParamInfo& p) {
  if (!p.dim || p.dim->dimensionless()) return p.name;
  return fmt::format("{} [{}]", p.name, lang::describe(*p.dim));
}

std::string format_result_table(const OptimizerResult& r, const CalibrationProblem& problem) {
  std::vector<std::string> head{"method", "samples", "evaluations", "accepted", "RMSE [K]", "R²"};
  std::vector<std::string> row{r.method, std::to_string(r.samples), std::to_string(r.evaluations),
                               std::to_string(r.accepted)};
  row.push_back(r.found ? fmt::format("{:.4f}", r.rmse) : "-");
  row.push_back(!r.found ? "-" : std::isnan(r.r2) ? "undefined" : fmt::format("{:.4f}", r.r2));
  for (std::size_t j = 0; j < problem.dimension(); ++j) {
    head.push_back(param_heading(problem.params()[j]));
    // With a least-squares fit, its standard error beside the value (also in --json).
    std::string value = r.found ? number(r.best[j]) : "-";
    if (r.found && j < r.std_errors.size() && std::isfinite(r.std_errors[j]))
      value += " ± " + number(r.std_errors[j]);
    row.push_back(value);
  }
  head.push_back("wall [s]");
  row.push_back(fmt::format("{:.2f}", r.wall_s));
  std::string top, rule, line;
  for (std::size_t c = 0; c < head.size(); ++c) {
    const std::size_t w = std::max(width_of(head[c]), width_of(row[c]));
    const std::string sep = c == 0 ? "" : "  ";
    top += sep + pad_left(head[c], w);
    rule += sep + std::string(w, '-');
    line += sep + pad_left(row[c], w);
  }
  return top + "\n" + rule + "\n" + line + "\n";
}

nlohmann::ordered_json result_json(const OptimizerResult& r, const CalibrationProblem& problem,
                                   const ReportContext& ctx) {
  using json = nlohmann::ordered_json;
  json j;
  j["method"] = r.method;
  j["samples"] = r.samples;
  j["evaluations"] = r.evaluations;
  j["accepted"] = r.accepted;
  j["rmse"] = r.found ? json(r.rmse) : json(nullptr);
  j["r2"] = r.found && !std::isnan(r.r2) ? json(r.r2) : json(nullptr);
  json params = json::object(), units = json::object(), declared = json::object();
  for (std::size_t k = 0; k < problem.dimension(); ++k) {
    const auto& p = problem.params()[k];
    if (r.found) params[p.name] = r.best[k];
    units[p.name] = p.dim ? lang::describe(*p.dim) : std::string("bare number");
    declared[p.name] = p.value;
  }
  j["params"] = params;
  j["wall_s"] = r.wall_s;
  j["units"] = "SI";
  j["param_units"] = units;
  j["declared"] = declared;
  j["found"] = r.found;
  j["cancelled"] = r.cancelled;
  j["simulations"] = r.simulations;
  j["seed"] = ctx.seed;
  j["tolerance_K"] = ctx.tolerance;
  j["model"] = ctx.model;
  j["cases"] = problem.cases();
  j["points"] = problem.points();
  if (!r.std_errors.empty()) {
    json se = json::object();
    for (std::size_t k = 0; k < problem.dimension() && k < r.std_errors.size(); ++k)
      se[problem.params()[k].name] = r.std_errors[k];
    j["std_errors"] = se;
  }
  if (!r.correlation.empty()) j["correlation"] = r.correlation;
  j["notes"] = r.notes;
  j["criterion"] = "output-error"; // the prediction criterion's report says otherwise
  return j;
}

plot::Figure comparison_figure(const std::vector<CalibrationProblem::CaseComparison>& cases,
                               const std::string& title) {
  plot::Figure fig;
  fig.title = title;
  for (const auto& c : cases) {
    plot::Panel panel;
    panel.title = "case " + c.case_name;
    panel.x_label = "time";
    panel.y_label = "temperature [°C]";
    panel.x_is_time_s = true;
    for (std::size_t s = 0; s < c.measured.series.size(); ++s) {
      const auto& ms = c.measured.series[s];
      plot::Series meas, sim;
      meas.label = ms.node + " measured";
      meas.style = plot::LineStyle::markers;
      sim.label = ms.node + " simulated";
      meas.color = sim.color = static_cast<int>(s);
      meas.x = sim.x = c.measured.times;
      for (double v : ms.values)
        meas.y.push_back(v - kZeroCelsius);
      for (double v : c.simulated[s])
        sim.y.push_back(v - kZeroCelsius);
      panel.series.push_back(std::move(meas));
      panel.series.push_back(std::move(sim));
    }
    fig.panels.push_back(std::move(panel));
  }
  return fig;
}

} // namespace thermnet::app
