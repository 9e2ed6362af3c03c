// `thermnet diagnose MODEL [--case NAME ...] [--json REPORT.json] [--write EXTENDED.tnet]
//  [--plot OUT.svg] [--threads N] [--top K] [--events EVENTS.csv] [--stats]
//  [--criterion output-error|prediction] [--initial-sd K] [--whiteness-plot OUT.svg]
//  [--jacobian differences|sensitivities] [--html REPORT.html]`

#include "cli/diagnose_command.hpp"

#include "app/diagnosis_output.hpp"

#include "app/diagnosis_html.hpp"
#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "app/option_rules.hpp"
#include "app/output_files.hpp"
#include "app/param_overrides.hpp"
#include "app/prediction_options.hpp"
#include "app/progress_bar.hpp"
#include "app/whiteness_figure.hpp"
#include "cli/run_command.hpp"
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
using namespace app;
namespace {

using lang::kZeroCelsius;

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

void add_diagnose_command(CLI::App& app, int& status) {
  auto o = std::make_shared<DiagnoseOptions>();
  CLI::App* sub = app.add_subcommand(
      "diagnose", "Find what a model gets wrong against measured data, its cause and the fix");
  sub->add_option("model", o->model, "model file (.tnet) whose cases carry measured data")
      ->required();
  sub->add_option("--case", o->cases, "diagnose only these cases (repeatable)");
  sub->add_option("--json", o->json, "write the report as JSON")->check(output_file_validator());
  sub->add_option("--html", o->html,
                  "write the report as one self-contained HTML page (baseline, findings with "
                  "their gains, rivals, lines and plots, residual diagnostics; docs/diagnose.md)")
      ->check(output_file_validator());
  sub->add_option("--write", o->write, "write the model with the best finding applied")
      ->check(output_file_validator());
  sub->add_option("--plot", o->plot, "write an SVG of before/after curves of the worst nodes")
      ->check(output_file_validator());
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
