// ModelSession: the CLI's loading, checking and reports, for callers that are not the CLI.

#include "python/model_session.hpp"

#include "app/calibration_report.hpp"
#include "app/model_loading.hpp"
#include "app/option_rules.hpp"
#include "app/param_overrides.hpp"
#include "app/sensitivity_report.hpp"
#include "kernel/calibration/optimizer.hpp"
#include "kernel/calibration/sensitivity.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/core/network.hpp"
#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/diagnosis/report.hpp"
#include "lang/diagnostics.hpp"
#include "lang/path_policy.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace thermnet::python {
namespace {

/// The place of a diagnostic: file, line and column (line 0 when it has no location).
LoadError error_at(const lang::Diagnostic& d, const lang::SourceManager& sources,
                   const std::string& message) {
  if (!d.at) return LoadError(message, d.file_hint, 0, 0);
  const lang::LineCol lc = sources.line_col(d.at->file, d.at->begin);
  return LoadError(message, sources.path(d.at->file), lc.line, lc.column);
}

/// Column of a node in a result, with a suggestion when it is unknown.
std::size_t column_of(const SimulationResult& r, const std::string& name) {
  auto it = std::find(r.names.begin(), r.names.end(), name);
  if (it != r.names.end()) return static_cast<std::size_t>(it - r.names.begin());
  std::string msg = fmt::format("the model has no node, boundary or sensor '{}'", name);
  if (auto s = lang::closest_match(name, r.names)) msg += fmt::format("; did you mean '{}'?", *s);
  throw std::invalid_argument(msg);
}

/// Keeps the named columns of a result, in the order asked.
SimulationResult select_nodes(SimulationResult r, const std::vector<std::string>& nodes) {
  if (nodes.empty()) return r;
  std::vector<std::size_t> cols;
  for (const auto& n : nodes)
    cols.push_back(column_of(r, n));
  SimulationResult out;
  out.names = nodes;
  out.times = std::move(r.times);
  out.stats = r.stats;
  for (const auto& row : r.temps) {
    std::vector<double> kept;
    for (std::size_t c : cols)
      kept.push_back(row[c]);
    out.temps.push_back(std::move(kept));
  }
  return out;
}

} // namespace

LoadError load_error_of(const lang::ModelError& e, const lang::SourceManager& sources) {
  lang::DiagnosticEngine one(sources);
  one.add(e.diag);
  return error_at(e.diag, sources, lang::render_text(one));
}

std::shared_ptr<const ModelSession>
ModelSession::checked(std::unique_ptr<lang::SourceManager> sources,
                      std::unique_ptr<lang::Model> model, lang::DiagnosticEngine& diags,
                      const std::string& path) {
  if (model) model->lint(diags);
  diags.sort();
  const auto& all = diags.all();
  auto first = std::find_if(all.begin(), all.end(), [](const lang::Diagnostic& d) {
    return d.severity == lang::Severity::error;
  });
  if (!model || first != all.end()) {
    if (first == all.end()) throw LoadError("cannot read " + path, path, 0, 0);
    throw error_at(*first, *sources, lang::render_text(diags));
  }
  auto s = std::make_shared<ModelSession>();
  s->sources_ = std::move(sources);
  s->model_ = std::move(model);
  s->policy_ = lang::path_policy(); // set by the load for the model's folder
  return s;
}

std::shared_ptr<const ModelSession> ModelSession::load(const std::string& path) {
  auto sources = std::make_unique<lang::SourceManager>();
  lang::DiagnosticEngine diags(*sources);
  auto model = app::load_model(path, *sources, diags);
  return checked(std::move(sources), std::move(model), diags, path);
}

std::shared_ptr<const ModelSession> ModelSession::from_text(const std::string& text,
                                                            const std::string& path) {
  auto sources = std::make_unique<lang::SourceManager>();
  lang::DiagnosticEngine diags(*sources);
  // As for a file: what the text names is read under the policy of the folder of `path`.
  lang::set_path_policy(lang::policy_for_model(path));
  auto model =
      lang::Model::from_text(path, text, element_catalog(), *sources, diags,
                             app::load_options(app::ModelPlugins::if_allowed, "thermnet (Python)"));
  return checked(std::move(sources), std::move(model), diags, path);
}

std::vector<std::string> ModelSession::node_names() const {
  std::vector<std::string> out;
  for (const auto& n : model_->nodes())
    out.emplace_back(n.name);
  return out;
}

std::vector<std::string> ModelSession::case_names() const {
  return model_->case_names();
}

SimulationResult ModelSession::simulate(const SimulateRequest& q) const {
  lang::set_path_policy(policy_); // files are read under this model's policy
  // The command line's rules, by the same code: `thermnet simulate`'s options and its --set.
  app::require(app::relative_tolerance_rule, q.rtol, "rtol");
  app::require(app::absolute_tolerance_rule, q.atol, "atol");
  if (q.duration) app::require(app::positive_number_rule, *q.duration, "duration");
  if (q.output) app::require(app::positive_number_rule, *q.output, "output");
  lang::Overrides values;
  for (const auto& [name, value] : q.params) {
    const std::string option = fmt::format("params['{}']", name);
    const app::SetTarget target = app::resolve_target(*model_, name, option);
    app::add_override(values, target, app::checked_value(target, value, option), option);
  }
  SimulationOptions opt;
  opt.duration = q.duration;
  opt.output = q.output;
  opt.steady = q.steady;
  opt.sensors = q.sensors;
  opt.solver.rtol = q.rtol;
  opt.solver.atol = q.atol;
  try {
    Network net(model_->instantiate(q.case_name, {}, values));
    SimulationResult r = thermnet::simulate(net, opt);
    // The rows carry the sensors' readings after the nodes; name their columns as the CLI does.
    if (q.sensors && r.names.size() == net.spec().nodes.size())
      for (int e : net.sensor_elements())
        r.names.push_back(net.spec().elements[static_cast<std::size_t>(e)].name);
    return select_nodes(std::move(r), q.nodes);
  } catch (const lang::ModelError& e) {
    throw load_error_of(e, *sources_);
  }
}

nlohmann::ordered_json ModelSession::calibrate(const CalibrateRequest& q) const {
  lang::set_path_policy(policy_); // files are read under this model's policy
  const OptimizerPlugin* plugin = OptimizerRegistry::global().find(q.method);
  if (!plugin) {
    std::string msg = fmt::format("unknown method '{}'", q.method);
    if (auto s = lang::closest_match(q.method, OptimizerRegistry::global().names()))
      msg += fmt::format("; did you mean '{}'?", *s);
    throw std::invalid_argument(msg);
  }
  app::require(app::positive_number_rule, q.tolerance, "tolerance");
  app::refuse_repeated_cases(q.cases);
  app::require(app::non_negative_whole_rule, q.threads, "threads");
  try {
    CalibrationProblem problem(*model_, q.cases);
    if (problem.dimension() == 0)
      throw std::invalid_argument("no param has a range; nothing to calibrate");
    if (problem.cases().empty())
      throw std::invalid_argument("no case has measured data; nothing to compare");
    OptimizerSettings settings;
    settings.samples = q.samples;
    settings.tolerance = q.tolerance;
    settings.seed = q.seed;
    settings.threads = q.threads;
    OptimizerResult r = plugin->create()->run(problem, settings);
    app::note_undefined_r2(r);
    return app::result_json(r, problem, app::ReportContext{q.seed, q.tolerance, model_->path()});
  } catch (const lang::ModelError& e) {
    throw load_error_of(e, *sources_);
  }
}

nlohmann::json ModelSession::diagnose(const std::vector<std::string>& cases, int threads,
                                      std::size_t top) const {
  lang::set_path_policy(policy_); // files are read under this model's policy
  app::require(app::non_negative_whole_rule, threads, "threads");
  app::require(app::positive_whole_rule, static_cast<double>(top), "top");
  app::refuse_repeated_cases(cases);
  DiagnosisOptions opt;
  opt.cases = cases;
  opt.threads = threads;
  opt.top = top;
  try {
    return diagnosis_json(thermnet::diagnose(*model_, opt));
  } catch (const lang::ModelError& e) {
    throw load_error_of(e, *sources_);
  }
}

nlohmann::json ModelSession::sensitivity(const std::vector<std::string>& cases, bool elements,
                                         int threads) const {
  lang::set_path_policy(policy_); // files are read under this model's policy
  app::require(app::non_negative_whole_rule, threads, "threads");
  app::refuse_repeated_cases(cases);
  SensitivityOptions opt;
  opt.cases = cases;
  opt.elements = elements;
  opt.threads = threads;
  try {
    return app::sensitivity_json(*model_, compute_sensitivities(*model_, opt));
  } catch (const lang::ModelError& e) {
    throw load_error_of(e, *sources_);
  }
}

} // namespace thermnet::python
