#include "app/calibration_html.hpp"

#include "app/report_page.hpp"
#include "lang/units.hpp"
#include "plot/html_page.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet::app {
namespace {

using plot::Align;
using plot::HtmlPage;
using plot::HtmlTable;

std::string unit_of(const lang::ParamInfo& p) {
  return p.dim && !p.dim->dimensionless() ? lang::describe(*p.dim) : std::string("—");
}

void add_run(HtmlPage& page, const CalibrationPage& in, bool prediction) {
  const OptimizerResult& r = *in.result;
  const CalibrationProblem& pb = *in.problem;
  page.open_section("run", "Run");
  std::vector<std::pair<std::string, std::string>> more = {
      {"criterion", prediction ? "prediction: maximum likelihood of a Kalman filter's "
                                 "one-step-ahead predictions (process and measurement noise "
                                 "fitted)"
                               : "output error: the simulation's RMSE against the measurements"},
      {"method", r.method},
      {"cases", fmt::format("{}: {}", pb.cases().size(), fmt::join(pb.cases(), ", "))},
      {"measured points", std::to_string(pb.points())}};
  // (samples, acceptance and the seed belong to the methods that draw: lm has none of them)
  const bool sampled = r.method == "mc" || r.method == "lhs";
  const bool seeded = sampled || r.method == "ga";
  more.emplace_back("evaluations",
                    sampled
                        ? fmt::format("{} ({} samples, {} accepted, {} case simulations)",
                                      r.evaluations, r.samples, r.accepted, r.simulations)
                        : fmt::format("{} ({} case simulations)", r.evaluations, r.simulations));
  if (!prediction && seeded) more.emplace_back("seed", std::to_string(in.context.seed));
  if (!prediction && sampled)
    more.emplace_back("acceptance limit",
                      page_number(in.context.tolerance, 4) + " K for every |T_sim − T_meas|");
  more.emplace_back("wall time", fmt::format("{:.2f} s", r.wall_s));
  add_run_facts(page, in.context.model, in.inputs, more);
  page.close_section();
}

void add_summary(HtmlPage& page, const OptimizerResult& r) {
  page.open_section("summary", "Summary");
  if (r.found)
    page.paragraph(
        fmt::format("Best fit: RMSE {} K, R² {}{}.", page_number(r.rmse, 4),
                    std::isnan(r.r2) ? std::string("undefined") : fmt::format("{:.4f}", r.r2),
                    r.cancelled ? " (interrupted: the best point so far)" : ""),
        "lead");
  else
    page.paragraph(r.cancelled ? "Interrupted before any acceptable point was found."
                               : "No acceptable parameter set was found.",
                   "lead");
  if (!r.notes.empty()) page.list(r.notes);
  page.close_section();
}

void add_params(HtmlPage& page, const CalibrationPage& in) {
  const OptimizerResult& r = *in.result;
  const CalibrationProblem& pb = *in.problem;
  page.open_section("params", "Parameters");
  HtmlTable t;
  t.caption = "Ranged params (SI units)";
  t.head = {"param", "unit",   "description",    "start",
            "range", "fitted", "standard error", "95 % interval (±1.96 SE)",
            "note"};
  t.align = {Align::left,  Align::left,  Align::left,  Align::right, Align::right,
             Align::right, Align::right, Align::right, Align::left};
  const auto start = pb.initial();
  for (std::size_t j = 0; j < pb.dimension(); ++j) {
    const auto& p = pb.params()[j];
    const double lo = p.lo.value_or(NAN), hi = p.hi.value_or(NAN);
    const double v = r.found && j < r.best.size() ? r.best[j] : NAN;
    const double se = r.found && j < r.std_errors.size() ? r.std_errors[j] : NAN;
    std::string note;
    const double span = std::abs(hi - lo);
    if (std::isfinite(v) && span > 0 && std::abs(v - lo) <= 1e-6 * span)
      note = "on its lower bound: a limit, not an estimate";
    else if (std::isfinite(v) && span > 0 && std::abs(v - hi) <= 1e-6 * span)
      note = "on its upper bound: a limit, not an estimate";
    t.rows.push_back(
        {p.name + (p.case_name.empty() ? "" : " (case " + p.case_name + ")"), unit_of(p), p.doc,
         page_number(start[j], 5), fmt::format("{} … {}", page_number(lo), page_number(hi)),
         page_number(v, 5), page_number(se, 3),
         std::isfinite(se)
             ? fmt::format("{} … {}", page_number(v - 1.96 * se), page_number(v + 1.96 * se))
             : std::string("—"),
         note});
  }
  page.table(t);
  if (r.std_errors.empty())
    page.paragraph(fmt::format("The {} method gives no standard errors: lm and --criterion "
                               "prediction do (from the Jacobian or the Hessian at the fit).",
                               r.method),
                   "note");
  if (!r.correlation.empty()) {
    HtmlTable c;
    c.caption = "Correlation of the fitted params";
    c.head = {""};
    c.align = {Align::left};
    for (std::size_t j = 0; j < pb.dimension(); ++j) {
      c.head.push_back(pb.params()[j].name);
      c.align.push_back(Align::right);
    }
    for (std::size_t i = 0; i < r.correlation.size() && i < pb.dimension(); ++i) {
      std::vector<std::string> row{pb.params()[i].name};
      for (const double x : r.correlation[i])
        row.push_back(page_number(x, 3));
      c.rows.push_back(std::move(row));
    }
    page.table(c);
  }
  if (in.prediction) {
    const auto& pc = *in.prediction;
    HtmlTable n;
    n.caption = "Noise parameters (fitted with the params)";
    n.head = {"parameter", "fitted", "standard error"};
    n.align = {Align::left, Align::right, Align::right};
    for (std::size_t k = pb.dimension(); k < pc.names.size() && k < pc.fit.theta.size(); ++k)
      n.rows.push_back(
          {pc.names[k], page_number(pc.fit.theta[k], 5),
           k < pc.fit.std_errors.size() ? page_number(pc.fit.std_errors[k], 3) : std::string("—")});
    if (!n.rows.empty()) page.table(n);
    page.facts({{"log-likelihood", page_number(pc.fit.log_likelihood, 7)},
                {"AIC / BIC",
                 fmt::format("{} / {}", page_number(pc.fit.aic, 7), page_number(pc.fit.bic, 7))},
                {"one-step-ahead RMSE", page_number(pc.one_step_rmse, 4) + " K"},
                {"quasi-Newton", fmt::format("{} iterations, {}", pc.fit.iterations,
                                             pc.fit.converged ? "converged" : "not converged")}});
  }
  page.close_section();
}

/// Fit per case: a table and the measured-vs-simulated figure; returns the residual series.
std::vector<CaseInnovations> add_cases(HtmlPage& page, const CalibrationPage& in) {
  const OptimizerResult& r = *in.result;
  std::vector<CaseInnovations> residuals;
  page.open_section("cases", "Fit per case");
  if (!r.found) {
    page.paragraph("No fit to show.");
    page.close_section();
    return residuals;
  }
  const auto cmp = in.problem->compare(r.best);
  HtmlTable t;
  t.caption = "Simulated with the fitted params against the measurements";
  t.head = {"case", "node", "points", "RMSE [K]", "bias [K]", "largest error [K]", "at t [s]"};
  t.align = {Align::left,  Align::left,  Align::right, Align::right,
             Align::right, Align::right, Align::right};
  for (const auto& c : cmp) {
    std::vector<std::string> nodes;
    std::vector<std::vector<double>> meas;
    for (std::size_t s = 0; s < c.measured.series.size() && s < c.simulated.size(); ++s) {
      const auto& ms = c.measured.series[s];
      double e2 = 0, e1 = 0, worst = 0, worst_t = NAN;
      std::size_t n = 0;
      for (std::size_t k = 0; k < ms.values.size() && k < c.simulated[s].size(); ++k) {
        if (std::isnan(ms.values[k])) continue;
        const double e = c.simulated[s][k] - ms.values[k];
        e2 += e * e, e1 += e, ++n;
        if (std::abs(e) > std::abs(worst)) worst = e, worst_t = c.measured.times[k];
      }
      const double dn = static_cast<double>(std::max<std::size_t>(n, 1));
      t.rows.push_back({c.case_name, ms.node, std::to_string(n), page_number(std::sqrt(e2 / dn), 3),
                        page_number(e1 / dn, 3), page_number(worst, 3), page_number(worst_t, 6)});
      nodes.push_back(ms.node);
      meas.push_back(ms.values);
    }
    residuals.push_back(simulated_series(
        c.case_name, c.measured.times, nodes, meas,
        {c.simulated.begin(), c.simulated.begin() + static_cast<long>(nodes.size())}));
  }
  page.table(t);
  auto fig = comparison_figure(cmp, "");
  fig.columns = cmp.size() > 1 ? 2 : 1;
  fig.panel_height = cmp.size() > 1 ? 300 : 380;
  page.figure(std::move(fig),
              "Measured (markers) and simulated (lines) temperatures with the fitted params, one "
              "panel per case.",
              "fit");
  page.close_section();
  return residuals;
}

void add_convergence(HtmlPage& page, const CalibrationPage& in) {
  if (in.convergence.size() < 2) return;
  page.open_section("convergence", "Convergence");
  plot::Panel panel;
  panel.x_label = "evaluations";
  panel.y_label = "best RMSE so far [K]";
  plot::Series s;
  s.label = in.result->method + ": best RMSE";
  s.color = 0;
  for (const auto& [done, rmse] : in.convergence) {
    s.x.push_back(done);
    s.y.push_back(rmse);
  }
  panel.series.push_back(std::move(s));
  plot::Figure fig;
  fig.panels.push_back(std::move(panel));
  fig.panel_height = 320;
  page.figure(std::move(fig),
              fmt::format("The best RMSE found by {} against the evaluations done (as its progress "
                          "reports came; the points before the first accepted one are left out).",
                          in.result->method),
              "convergence");
  page.close_section();
}

} // namespace

void ConvergenceTrace::record(const Progress& p) {
  if (!std::isfinite(p.best_rmse)) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  points_.emplace_back(static_cast<double>(p.done), p.best_rmse);
}

std::vector<std::pair<double, double>> ConvergenceTrace::points() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  auto v = points_;
  // Reports from several threads may arrive out of order.
  std::stable_sort(v.begin(), v.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  return v;
}

std::string calibration_html(const CalibrationPage& in) {
  const bool prediction = in.prediction != nullptr;
  HtmlPage page("thermnet calibrate — " + in.model->name());
  add_run(page, in, prediction);
  add_summary(page, *in.result);
  add_params(page, in);
  const auto residuals = add_cases(page, in);
  add_convergence(page, in);
  page.open_section("residuals", "Residual diagnostics");
  if (prediction) {
    page.paragraph("The innovations (one-step-ahead prediction errors) at the fit: white "
                   "innovations mean the model and its noise describe the dynamics; structure left "
                   "in them shows as autocorrelation beyond the band and a cumulated periodogram "
                   "that leaves its band.");
    add_whiteness(page, in.prediction->whiteness, "innovations", "whiteness");
  } else if (!residuals.empty()) {
    page.paragraph("The simulation residuals (measured − simulated) at the fit. Output-error "
                   "residuals are rarely white (they carry the slow drift of what the model "
                   "misses); the bounds are those of white noise, for reference. (--criterion "
                   "prediction tests the innovations, which should be white.)");
    add_whiteness(page, test_innovations(residuals), "simulation residuals", "whiteness");
  } else {
    page.paragraph("No fit to test.");
  }
  page.close_section();
  page.paragraph("Written by thermnet " + std::string(THERMNET_VERSION) +
                     " (thermnet calibrate --html): one self-contained file, no script and no "
                     "external resource. Temperatures in °C on the plots, differences in K; "
                     "parameters in SI units.",
                 "note");
  return page.str();
}

} // namespace thermnet::app
