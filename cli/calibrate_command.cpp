// `thermnet calibrate MODEL [--method NAME] [--samples N] [--tolerance T] [--seed S] [--threads N]
//  [-o CALIBRATED.tnet] [--json REPORT.json] [--plot OUT.svg] [--case NAME ...]
//  [--criterion output-error|prediction] [--initial-sd K] [--whiteness-plot OUT.svg]
//  [--html REPORT.html]`
//
// Ctrl-C (under mpirun also SIGTERM, which mpirun sends the ranks for a Ctrl-C) sets a flag the
// optimizer polls: it stops drawing samples, returns the best so far, and the command still writes
// its outputs, then exits 1 with "interrupted; best result so far written". A second signal kills
// the process (the handlers are one-shot).

#include "cli/calibrate_command.hpp"

#include "app/calibration_html.hpp"
#include "app/calibration_report.hpp"
#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "app/option_rules.hpp"
#include "app/output_files.hpp"
#include "app/param_overrides.hpp"
#include "app/prediction_calibration.hpp"
#include "app/prediction_options.hpp"
#include "app/progress_bar.hpp"
#include "app/whiteness_figure.hpp"
#include "cli/run_command.hpp"
#include "kernel/calibration/optimizer.hpp"
#include "kernel/core/process_group.hpp"
#include "lang/rewrite/model_files.hpp"

#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <memory>
#include <thread>

namespace thermnet::cli {
using namespace app;
namespace {

struct CalibrateOptions {
  std::string model;
  std::string method;
  std::size_t samples = 0;
  double tolerance = 5.0;
  std::uint64_t seed = 1;
  int threads = 0;
  std::string out;
  std::string json;
  std::string html;
  std::string plot;
  std::vector<std::string> cases;
  std::vector<std::string> sets;
  PredictionOptions prediction;
  std::string predictions;
};

std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the interrupt flag must be lock-free");

extern "C" void on_interrupt(int) {
  g_interrupted.store(true);
}

/// Installs a one-shot handler of SIGINT (Ctrl-C) for its lifetime and restores the previous one
/// after. Under mpirun also of SIGTERM: mpirun passes a Ctrl-C on to the ranks as SIGTERM (and
/// kills them a second later), so that is a rank's Ctrl-C. A single process keeps SIGTERM's
/// meaning: terminate at once, writing nothing.
class InterruptGuard {
public:
  InterruptGuard() {
    g_interrupted = false;
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND; // a second signal terminates as usual
    const std::size_t count = process_group().size() > 1 ? std::size(kSignals) : 1;
    for (std::size_t k = 0; k < count; ++k)
      installed_[k] = sigaction(kSignals[k], &sa, &old_[k]) == 0;
  }
  ~InterruptGuard() {
    for (std::size_t k = 0; k < std::size(kSignals); ++k)
      if (installed_[k]) sigaction(kSignals[k], &old_[k], nullptr);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

private:
  static constexpr int kSignals[] = {SIGINT, SIGTERM};
  struct sigaction old_[std::size(kSignals)]{};
  bool installed_[std::size(kSignals)] = {};
};

std::string default_method() {
  return OptimizerRegistry::global().find("auto") ? "auto" : "mc";
}

std::string methods_help() {
  std::string s = "calibration method (default: " + default_method() + "):";
  for (const auto& name : OptimizerRegistry::global().names())
    s += fmt::format("\n  {}: {}", name, OptimizerRegistry::global().find(name)->doc);
  return s;
}

CLI::Validator method_validator() {
  return CLI::Validator(
      [](std::string& name) -> std::string {
        const auto& reg = OptimizerRegistry::global();
        if (reg.find(name)) return {};
        std::string msg = fmt::format("unknown method '{}'", name);
        if (auto s = lang::closest_match(name, reg.names()))
          msg += fmt::format("; did you mean '{}'?", *s);
        return msg + fmt::format(" (methods: {})", fmt::join(reg.names(), ", "));
      },
      "METHOD");
}

/// Writes the requested outputs as one unit: nothing is written unless everything could be.
/// The written model reads the files it did not copy (its data, unchanged includes) where they
/// are: should one lie outside the new model's folder, reading it again needs
/// --allow-outside-paths; says so.
void note_files_outside(const std::string& out, const lang::Model& model,
                        const std::vector<rewrite::RewrittenFile>& written) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto canonical = [&ec](const std::string& p) {
    return fs::weakly_canonical(fs::absolute(p, ec), ec);
  };
  const fs::path folder = canonical(out).parent_path();
  std::vector<std::string> outside;
  for (const auto& in : model_inputs(model)) {
    const bool copied = std::any_of(written.begin(), written.end(), [&](const auto& f) {
      return canonical(model.sources().path(f.source)) == canonical(in.path);
    });
    const fs::path rel = canonical(in.path).lexically_relative(folder);
    if (!copied && (rel.empty() || *rel.begin() == "..")) outside.push_back(in.path);
  }
  if (outside.empty()) return;
  std::cerr << fmt::format("thermnet calibrate: note: {} reads files outside its own folder ({}); "
                           "a model may read them only with --allow-outside-paths\n",
                           out, fmt::join(outside, ", "));
}

void write_outputs(const CalibrateOptions& o, const lang::Model& model,
                   const CalibrationProblem& problem, const OptimizerResult& r,
                   const nlohmann::ordered_json& json, std::vector<OutputFile> files) {
  if (!o.json.empty()) files.push_back({o.json, json.dump(2) + "\n"});
  std::vector<rewrite::RewrittenFile> model_files;
  if (r.found && !o.out.empty()) {
    std::vector<rewrite::ParamUpdate> updates;
    for (std::size_t j = 0; j < problem.dimension(); ++j)
      updates.push_back({problem.params()[j], r.best[j]});
    const long root = model.sources().find(model.path());
    if (root < 0) throw OutputError("the model's own text is no longer available");
    model_files =
        rewrite::rewrite_model(model.sources(), static_cast<lang::FileId>(root), updates, o.out);
    for (const auto& f : model_files)
      files.push_back({f.path, f.text, f.chosen ? Follow::never : Follow::symlinks});
  }
  if (r.found && !o.plot.empty()) {
    auto cmp = problem.compare(r.best);
    std::string title =
        fmt::format("{} — calibrated by {} (RMSE {:.3g} K)", model.name(), r.method, r.rmse);
    files.push_back({o.plot, plot::render_svg(comparison_figure(cmp, title))});
  }
  write_output_files(files);
  if (model_files.size() > 1) {
    std::vector<std::string> copies;
    for (std::size_t k = 1; k < model_files.size(); ++k)
      copies.push_back(fmt::format("{} (copy of {})", model_files[k].path,
                                   model.sources().path(model_files[k].source)));
    std::cerr << fmt::format("thermnet calibrate: note: {} includes rewritten copies of the files "
                             "declaring calibrated params, written beside it: {}\n",
                             o.out, fmt::join(copies, ", "));
  }
  if (!model_files.empty()) {
    note_files_outside(o.out, model, model_files);
    note_sets_not_written(model, "thermnet calibrate", o.out);
  }
}

/// --criterion prediction: maximum likelihood of the one-step-ahead predictions.
int run_prediction(const CalibrateOptions& o, const lang::Model& model,
                   const CalibrationProblem& problem) {
  const char* me = "thermnet calibrate";
  std::cerr << fmt::format("{}: {} param{} and the noise over {} case{} ({} measured points), "
                           "criterion prediction (maximum likelihood, Kalman filter)\n",
                           me, problem.dimension(), problem.dimension() == 1 ? "" : "s",
                           problem.cases().size(), problem.cases().size() == 1 ? "" : "s",
                           problem.points());
  const auto pc = calibrate_by_prediction(model, problem, o.prediction.initial_sd, o.threads,
                                          {o.seed, o.tolerance, o.model});
  std::cout << pc.text;
  std::cout.flush();
  for (const auto& note : pc.result.notes)
    std::cerr << fmt::format("{}: note: {}\n", me, note);
  std::vector<OutputFile> extra;
  if (pc.result.found && !o.prediction.whiteness_plot.empty())
    extra.push_back({o.prediction.whiteness_plot,
                     plot::render_svg(whiteness_figure(
                         pc.whiteness, fmt::format("{} — innovations of the one-step-ahead "
                                                   "predictions (log-likelihood {:.5g})",
                                                   model.name(), pc.fit.log_likelihood)))});
  if (pc.result.found && !o.predictions.empty())
    extra.push_back({o.predictions, predictions_csv(pc.innovations)});
  if (!o.html.empty())
    extra.push_back({o.html, calibration_html({&model,
                                               &problem,
                                               &pc.result,
                                               {o.seed, o.tolerance, o.model},
                                               model_inputs(model),
                                               {},
                                               &pc})});
  write_outputs(o, model, problem, pc.result, pc.json, std::move(extra));
  if (!pc.result.found) {
    std::cerr << fmt::format("{}: error: the likelihood cannot be evaluated at the start\n", me);
    return exit_failure;
  }
  return exit_ok;
}

int run_calibrate(const CalibrateOptions& o, lang::SourceManager& sources) {
  const char* me = "thermnet calibrate";
  int status = exit_ok;
  auto model = load_checked_model(o.model, sources, status, o.sets);
  if (!model) return status;
  check_outputs({{"-o", o.out},
                 {"--json", o.json},
                 {"--html", o.html},
                 {"--plot", o.plot},
                 {"--whiteness-plot", o.prediction.whiteness_plot},
                 {"--predictions", o.predictions}},
                model_inputs(*model));
  const bool prediction = o.prediction.prediction();
  if ((!o.prediction.whiteness_plot.empty() || !o.predictions.empty()) && !prediction) {
    std::cerr << fmt::format("{}: error: {} needs --criterion prediction (it writes the "
                             "one-step-ahead prediction errors of that criterion)\n",
                             me, o.predictions.empty() ? "--whiteness-plot" : "--predictions");
    return exit_usage;
  }
  if (prediction && !o.method.empty()) {
    std::cerr << fmt::format("{}: error: --method does not apply to --criterion prediction (the "
                             "likelihood is maximised by a quasi-Newton method)\n",
                             me);
    return exit_usage;
  }
  const std::string method = o.method.empty() ? default_method() : o.method;
  const OptimizerPlugin* plugin = OptimizerRegistry::global().find(method);
  if (!plugin) {
    std::cerr << fmt::format("{}: error: unknown method '{}'\n", me, method);
    return exit_usage;
  }
  refuse_repeated_cases(o.cases);
  CalibrationProblem problem(*model, o.cases);
  if (problem.dimension() == 0 && !prediction) {
    std::cerr << fmt::format("{}: error: no param in {} has a range; nothing to calibrate "
                             "(declare one as e.g. `param h = 5 [W/(m^2*K)] range 2 .. 10`)\n",
                             me, o.model);
    return exit_failure;
  }
  if (problem.cases().empty()) {
    std::cerr << fmt::format("{}: error: no case in {} has measured data; nothing to compare "
                             "(add `data \"file.csv\"` to a case)\n",
                             me, o.model);
    return exit_failure;
  }
  if (prediction) return run_prediction(o, *model, problem);
  OptimizerSettings settings;
  settings.samples = o.samples;
  settings.tolerance = o.tolerance;
  settings.seed = o.seed;
  settings.threads = o.threads;
  const unsigned threads = o.threads > 0 ? static_cast<unsigned>(o.threads)
                                         : std::max(1u, std::thread::hardware_concurrency());
  std::cerr << fmt::format(
      "{}: {} param{} over {} case{} ({} measured points), method {}, {} thread{}\n", me,
      problem.dimension(), problem.dimension() == 1 ? "" : "s", problem.cases().size(),
      problem.cases().size() == 1 ? "" : "s", problem.points(), method, threads,
      threads == 1 ? "" : "s");

  OptimizerResult r;
  ConvergenceTrace trace; // for --html: the best RMSE as the search went
  {
    ProgressBar bar(progress_wanted());
    const bool trace_wanted = !o.html.empty();
    settings.on_progress = [&bar, &trace, trace_wanted](const Progress& p) {
      bar.update(p);
      if (trace_wanted) trace.record(p);
    };
    InterruptGuard guard;
    settings.cancel = &g_interrupted;
    r = plugin->create()->run(problem, settings);
    bar.finish();
    settings.on_progress = nullptr; // the bar goes out of scope
    if (g_interrupted) r.cancelled = true;
  }
  note_undefined_r2(r);

  std::cout << format_result_table(r, problem);
  std::cout << "(param values in SI units)\n";
  std::cout << "criterion: output error (the simulation's RMSE against the measurements)\n";
  std::cout.flush();
  for (const auto& note : r.notes)
    std::cerr << fmt::format("{}: note: {}\n", me, note);
  auto json = result_json(r, problem, {o.seed, o.tolerance, o.model});
  std::vector<OutputFile> extra;
  if (!o.html.empty())
    extra.push_back({o.html, calibration_html({model.get(),
                                               &problem,
                                               &r,
                                               {o.seed, o.tolerance, o.model},
                                               model_inputs(*model),
                                               trace.points(),
                                               nullptr})});
  write_outputs(o, *model, problem, r, json, std::move(extra));
  if (r.cancelled) {
    // Under mpirun only rank 0 writes; the others say so (their words are shown only if they
    // differ from rank 0's).
    std::cerr << fmt::format("{}: interrupted; {}\n", me,
                             !r.found                      ? "no result to write"
                             : process_group().rank() == 0 ? "best result so far written"
                                                           : "rank 0 writes the best result");
    return exit_failure;
  }
  if (!r.found) {
    std::cerr << fmt::format("{}: error: no acceptable parameter set was found\n", me);
    return exit_failure;
  }
  return exit_ok;
}

} // namespace

void add_calibrate_command(CLI::App& app, int& status) {
  auto o = std::make_shared<CalibrateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate", "Fit the ranged params to the measured data of the cases (Monte Carlo, ...)");
  cmd->add_option("MODEL", o->model, "model file (.tnet)")->required();
  cmd->add_option("--method", o->method, methods_help())->check(method_validator());
  cmd->add_option("--samples", o->samples, "number of samples (default: 3000 for mc and lhs)")
      ->check(rule_validator(positive_whole_rule, "INT"));
  cmd->add_option("--tolerance", o->tolerance,
                  "acceptance limit |T_sim - T_meas| in degC (K), default 5")
      ->check(rule_validator(positive_number_rule, "NUMBER"));
  cmd->add_option("--seed", o->seed, "random seed (same seed, same result), default 1")
      ->check(rule_validator(non_negative_whole_rule, "INT"));
  cmd->add_option("--threads", o->threads, "worker threads (default 0: all cores)")
      ->check(rule_validator(non_negative_whole_rule, "INT"));
  cmd->add_option("-o,--out", o->out,
                  "write the model with the calibrated values in place (comments and layout "
                  "kept, units as written); params declared in included files go to rewritten "
                  "copies beside OUT named OUTSTEM.FILE, which OUT includes instead of the "
                  "originals; the inputs are never modified (OUT may not be one of them), "
                  "and nothing is written unless every output can be")
      ->check(output_file_validator());
  cmd->add_option("--json", o->json, "write the result as JSON")->check(output_file_validator());
  cmd->add_option("--html", o->html,
                  "write the report as one self-contained HTML page (params with start, range, "
                  "fit and interval; fit per case; convergence; residual diagnostics; "
                  "docs/calibration.md)")
      ->check(output_file_validator());
  cmd->add_option("--plot", o->plot, "SVG plot of measured vs simulated for the best fit")
      ->check(output_file_validator());
  cmd->add_option("--case", o->cases,
                  "cases to compare (repeat --case or separate by commas; default: all with data)")
      ->allow_extra_args(false)
      ->delimiter(',');
  add_prediction_options(
      cmd, o->prediction,
      "what the fit minimises: output-error (default: the simulation's RMSE) or "
      "prediction (the likelihood of a Kalman filter's one-step-ahead predictions, "
      "with process and measurement noise fitted; docs/calibration.md)",
      "prediction: SVG of the innovations' autocorrelation and cumulated periodogram "
      "with their white-noise bounds");
  cmd->add_option("--predictions", o->predictions,
                  "prediction: CSV of the one-step-ahead predictions at the fit "
                  "(case,time,node,measured,predicted,sd; degC and K)");
  add_set_option(cmd, o->sets,
                 "; a ranged param set this way keeps its range and starts the fit there "
                 "(lm; the sampling methods draw over the range); -o does not write these values");
  cmd->callback([o, &status] {
    status = run_command("thermnet calibrate",
                         [&](lang::SourceManager& sources) { return run_calibrate(*o, sources); });
  });
}

} // namespace thermnet::cli
