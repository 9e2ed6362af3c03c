// `thermnet diagnose MODEL [--case NAME ...] [--json REPORT.json] [--write EXTENDED.tnet]
//  [--plot OUT.svg] [--threads N] [--top K] [--events EVENTS.csv] [--stats]
//  [--criterion output-error|prediction] [--initial-sd K] [--whiteness-plot OUT.svg]
//  [--jacobian differences|sensitivities] [--html REPORT.html]`

#include "cli/diagnose_command.hpp"

#include "cli/diagnosis_html.hpp"
#include "cli/exit_status.hpp"
#include "cli/model_loading.hpp"
#include "cli/option_rules.hpp"
#include "cli/output_files.hpp"
#include "cli/param_overrides.hpp"
#include "cli/prediction_options.hpp"
#include "cli/progress_bar.hpp"
#include "cli/run_command.hpp"
#include "cli/whiteness_figure.hpp"
#include "kernel/diagnosis/report.hpp"
#include "lang/path_policy.hpp"
#include "lang/rewrite/case_blocks.hpp"
#include "lang/rewrite/param_values.hpp"
#include "lang/units.hpp"
#include "plot/style.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <memory>

namespace thermnet::cli {
namespace {

using lang::kZeroCelsius;

/// Palette indices of the plot's worst nodes, in rank order: the first ones as far apart as the
/// palette allows (blue, vermillion, black, orange), so no two nodes of a panel look alike.
constexpr std::array<int, 8> kNodeColors = {0, 1, 6, 4, 3, 5, 2, 7};

struct DiagnoseOptions {
  std::string model;
  std::vector<std::string> cases;
  std::string json;
  std::string html;
  std::string write;
  std::string plot;
  std::string events;
  int threads = 0;
  std::size_t top = 5;
  std::size_t case_folds = DiagnosisOptions{}.case_folds;
  double min_gain = DiagnosisOptions{}.min_gain;
  std::vector<std::string> sets;
  bool stats = false;
  PredictionOptions prediction;
  std::string jacobian = "differences";
};

int run_diagnose(const DiagnoseOptions& o, lang::SourceManager& sources) {
  const char* me = "thermnet diagnose";
  int status = exit_ok;
  auto model = load_checked_model(o.model, sources, status, o.sets);
  if (!model) return status;
  auto inputs = model_inputs(*model);
  if (!o.events.empty()) inputs.push_back({o.events, "the events file"});
  check_outputs({{"--json", o.json},
                 {"--html", o.html},
                 {"--write", o.write},
                 {"--plot", o.plot},
                 {"--whiteness-plot", o.prediction.whiteness_plot}},
                inputs);
  if (!o.prediction.whiteness_plot.empty() && !o.prediction.prediction()) {
    std::cerr << fmt::format("{}: error: --whiteness-plot needs --criterion prediction (the "
                             "whiteness tests are of its one-step-ahead prediction errors)\n",
                             me);
    return exit_usage;
  }
  DiagnosisOptions opt;
  if (!o.events.empty()) {
    // The user named it: the model-folder rule (for the files a model names) does not apply.
    lang::allow_named_path(o.events);
    opt.events = read_events(o.events, model->run_case_names());
    opt.events_path = o.events;
  }
  refuse_repeated_cases(o.cases);
  opt.cases = o.cases;
  opt.threads = o.threads;
  opt.top = o.top;
  opt.case_folds = o.case_folds;
  opt.criterion = o.prediction.criterion;
  opt.sensitivities = o.jacobian == "sensitivities";
  opt.initial_sd = o.prediction.initial_sd;
  opt.min_gain = o.min_gain;
  // On a terminal, a line says what the diagnosis is doing (a data file of 10^6 rows takes
  // minutes): its stage, the refits done, the time so far.
  ProgressBar bar(progress_wanted());
  if (progress_wanted())
    opt.progress = [&bar](const DiagnosisProgress& p) {
      bar.show(p.total == 0
                   ? fmt::format("thermnet diagnose: {} ({:.0f} s)", p.stage, bar.elapsed())
                   : fmt::format("thermnet diagnose: {} {}/{} ({:.0f} s)", p.stage, p.done, p.total,
                                 bar.elapsed()),
               p.done == 0 || p.done == p.total);
    };
  const DiagnosisReport rep = diagnose(*model, opt);
  bar.finish();
  std::cout << diagnosis_text(rep);
  std::cout.flush();
  if (o.stats) std::cerr << diagnosis_timing_text(rep);
  std::vector<OutputFile> files;
  if (!o.json.empty()) files.push_back({o.json, diagnosis_json(rep).dump(2) + "\n"});
  if (!o.html.empty()) files.push_back({o.html, diagnosis_html(rep, *model, inputs)});
  if (!o.write.empty()) {
    if (rep.findings.empty())
      std::cerr << fmt::format("{}: note: no finding; {} not written\n", me, o.write);
    else
      for (auto& f : extended_model_files(*model, rep.findings.front(), o.write))
        files.push_back({f.path, std::move(f.text), f.chosen ? Follow::never : Follow::symlinks});
  }
  if (!o.plot.empty()) files.push_back({o.plot, diagnosis_svg(rep, model->name())});
  if (!o.prediction.whiteness_plot.empty() && rep.prediction) {
    const auto& p = *rep.prediction;
    const bool found = !rep.findings.empty();
    files.push_back(
        {o.prediction.whiteness_plot,
         plot::render_svg(whiteness_figure(
             found ? p.whiteness_after : p.whiteness_before,
             fmt::format("{} — innovations {} (log-likelihood {:.5g})", model->name(),
                         found ? "with the findings" : "of the declared structure",
                         found ? p.final_fit.log_likelihood : p.declared.log_likelihood)))});
  }
  write_output_files(files);
  if (!o.write.empty() && !rep.findings.empty()) note_sets_not_written(*model, me, o.write);
  return exit_ok;
}

} // namespace

std::string finding_comment(const Finding& f) {
  return fmt::format(
      "# thermnet diagnose: {} [{}]{} -- {}\n# RMSE {:.4g} -> {:.4g} K (held-out {:.4g} -> "
      "{:.4g} K)\n",
      f.candidate.kind, fmt::join(f.candidate.nodes, ", "),
      f.candidate.mechanism.empty() ? "" : " (" + f.candidate.mechanism + ")", f.evidence,
      f.rmse_before, f.rmse_after, f.validation_rmse_before, f.validation_rmse_after);
}

std::string finding_lines(const Finding& f) {
  std::string s = finding_comment(f);
  for (const auto& name : f.retired)
    s += fmt::format("# (the declaration of {} is commented out: the lines below replace it)\n",
                     name);
  if (!f.param_rewrites.empty()) {
    s += "# (the declared values of the ranged params are rewritten:)\n";
    for (const auto& [name, value] : f.param_rewrites)
      s += fmt::format("#   {} = {} (SI)\n", name, netlist_number(value));
  } else if (!f.statement.empty()) {
    s += f.statement + "\n";
  }
  for (const auto& [name, lines] : f.case_statements)
    s += fmt::format("# inside case {} {{ ... }}:\n{}\n", name, lines);
  return s;
}

std::vector<rewrite::RewrittenFile> extended_model_files(const lang::Model& model, const Finding& f,
                                                         const std::string& out) {
  const long root = model.sources().find(model.path());
  if (root < 0) throw OutputError("the model's own text is no longer available");
  const auto file = static_cast<lang::FileId>(root);
  const std::string why = finding_comment(f);
  // The ranged params it recalibrated are rewritten where they are declared (an included file
  // is written as a rewritten copy beside the output, as calibrate -o does).
  std::vector<rewrite::ParamUpdate> updates;
  std::string applied;
  if (!f.param_rewrites.empty()) {
    for (const auto& p : model.params())
      if (auto it = f.param_rewrites.find(p.name); it != f.param_rewrites.end())
        updates.push_back({p, it->second});
    applied = "# (the declared values of the ranged params were rewritten)\n";
  } else {
    applied = f.statement.empty() ? "" : f.statement + "\n";
  }
  std::vector<std::string> elsewhere;
  auto edits = rewrite::case_block_edits(model, file, f.case_statements,
                                         "# thermnet diagnose: " + f.candidate.kind, elsewhere);
  if (!edits.empty()) applied += "# (with the lines marked in the case blocks above)\n";
  // The declarations the finding's statements replace are kept as comments.
  const std::string& text = model.sources().text(file);
  for (const auto& name : f.retired)
    for (const auto& d : model.elements())
      if (d.name == name && d.file == file && !d.scope) {
        const lang::Span where = d.where();
        std::string old = text.substr(where.begin, where.end - where.begin), commented = "# ";
        for (char ch : old)
          commented += ch == '\n' ? std::string("\n# ") : std::string(1, ch);
        edits.push_back({where.begin, where.end,
                         commented + "  # replaced by thermnet diagnose: " + f.candidate.kind});
      }
  for (const auto& name : elsewhere) {
    applied +=
        fmt::format("# not applied: case {} is not in this file; add inside its block:\n", name);
    std::string lines = f.case_statements.at(name);
    for (auto p = lines.find('\n'); p != std::string::npos; p = lines.find('\n', p + 5))
      lines.replace(p, 1, "\n#   ");
    applied += "#   " + lines + "\n";
  }
  auto files = rewrite::rewrite_model(model.sources(), file, updates, out, std::move(edits));
  std::string& written = files.front().text;
  if (!written.empty() && written.back() != '\n') written += '\n';
  written += "\n" + why + applied;
  return files;
}

std::string extended_model_text(const lang::Model& model, const Finding& f) {
  return extended_model_files(model, f, model.path() + ".extended.tnet").front().text;
}

std::string diagnosis_svg(const DiagnosisReport& r, const std::string& model_name,
                          std::size_t worst) {
  const std::string title = r.findings.empty() ? fmt::format("{} — no finding", model_name)
                                               : fmt::format("{} — before and after {}", model_name,
                                                             r.findings.front().candidate.kind);
  return plot::render_svg(diagnosis_figure(r, title, worst, true));
}

plot::Figure diagnosis_figure(const DiagnosisReport& r, const std::string& title, std::size_t worst,
                              bool with_after) {
  std::vector<std::pair<std::string, double>> nodes;
  for (const auto& [name, m] : r.baseline.nodes)
    nodes.emplace_back(name, m.rmse);
  std::stable_sort(nodes.begin(), nodes.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  // One colour per node: never more nodes than distinct colours.
  worst = std::min({worst, kNodeColors.size(), static_cast<std::size_t>(plot::palette_size())});
  if (nodes.size() > worst) nodes.resize(worst);
  plot::Figure fig;
  fig.title = title;
  for (const auto& cv : r.curves) {
    plot::Panel panel;
    panel.title = "case " + cv.case_name + " (worst nodes)";
    panel.x_label = "time";
    panel.y_label = "temperature [°C]";
    panel.x_is_time_s = true;
    for (std::size_t rank = 0; rank < nodes.size(); ++rank) {
      const std::string& name = nodes[rank].first;
      auto add = [&](const std::map<std::string, std::vector<double>>& m, const std::string& label,
                     plot::LineStyle style) {
        auto it = m.find(name);
        if (it == m.end() || it->second.empty()) return;
        plot::Series s;
        s.label = name + " " + label;
        s.style = style;
        s.color = kNodeColors[rank];
        s.x = cv.times;
        for (double v : it->second)
          s.y.push_back(v - kZeroCelsius);
        panel.series.push_back(std::move(s));
      };
      add(cv.measured, "measured", plot::LineStyle::markers);
      add(cv.before, with_after ? "before" : "simulated", plot::LineStyle::solid);
      if (with_after) add(cv.after, "after", plot::LineStyle::dashed);
    }
    fig.panels.push_back(std::move(panel));
  }
  return fig;
}

void add_diagnose_command(CLI::App& app, int& status) {
  auto o = std::make_shared<DiagnoseOptions>();
  CLI::App* sub = app.add_subcommand(
      "diagnose", "Find what a model gets wrong against measured data, its cause and the fix");
  sub->add_option("model", o->model, "model file (.tnet) whose cases carry measured data")
      ->required();
  sub->add_option("--case", o->cases, "diagnose only these cases (repeatable)");
  sub->add_option("--json", o->json, "write the report as JSON");
  sub->add_option("--html", o->html,
                  "write the report as one self-contained HTML page (baseline, findings with "
                  "their gains, rivals, lines and plots, residual diagnostics; docs/diagnose.md)");
  sub->add_option("--write", o->write, "write the model with the best finding applied");
  sub->add_option("--plot", o->plot, "write an SVG of before/after curves of the worst nodes");
  sub->add_option("--threads", o->threads, "worker threads (0: all cores)")
      ->check(rule_validator(non_negative_whole_rule, "INT"));
  sub->add_option("--top", o->top, "most findings reported")
      ->check(rule_validator(positive_whole_rule, "INT"));
  sub->add_option("--case-folds", o->case_folds,
                  "most validation folds of cases held out whole (default 5): with more cases, "
                  "case i joins fold i mod N; as many as the cases: leave one case out")
      ->check(rule_validator(at_least_two_whole_rule, "INT"));
  sub->add_option("--min-gain", o->min_gain,
                  "practical floor, K: no finding that lowers the RMS error over 10 consecutive "
                  "samples of a series by less than this (default 0.05)")
      ->check(rule_validator(non_negative_number_rule, "NUMBER"));
  add_set_option(sub, o->sets, "; the model diagnosed has them (--write does not write them)");
  sub->add_option("--events", o->events,
                  "CSV of known events: windows (case,event,start,end in s; empty case: every "
                  "case) or a campaign's log (time,event: \"Lid Opened\", \"Lid Closed\"; UNIX "
                  "times placed by each case's data): event_loss looks for a loss that exists "
                  "only while one is on");
  add_prediction_options(
      sub, o->prediction,
      "how candidates are compared: output-error (default: simulation residuals, "
      "held-out validation) or prediction (maximum likelihood of a Kalman filter's "
      "one-step-ahead predictions, likelihood-ratio tests; docs/diagnose.md)",
      "prediction: SVG of the innovations' autocorrelation and cumulated periodogram "
      "(with the findings applied) with their white-noise bounds");
  sub->add_option("--jacobian", o->jacobian,
                  "output-error: the refits' Jacobians by differences (default: forward "
                  "differences of simulations) or sensitivities (CVODES forward sensitivities; "
                  "fewer simulations, near-tied fits may end elsewhere; docs/diagnose.md)")
      ->check(CLI::IsMember({"differences", "sensitivities"}));
  sub->add_flag("--stats", o->stats,
                "print where the time went (setup, each batch of refits) to standard error");
  sub->callback([o, &status] {
    status = run_command("thermnet diagnose",
                         [&](lang::SourceManager& sources) { return run_diagnose(*o, sources); });
  });
}

} // namespace thermnet::cli
