#include "cli/estimate_command.hpp"

#include "app/csv_writer.hpp"
#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "app/option_rules.hpp"
#include "app/output_files.hpp"
#include "app/output_stream.hpp"
#include "app/param_overrides.hpp"
#include "cli/run_command.hpp"
#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/estimation/estimator.hpp"
#include "lang/csv.hpp"
#include "lang/diagnostics.hpp"
#include "lang/measured_series.hpp"
#include "lang/path_policy.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace thermnet::cli {
using namespace app;
namespace {

struct EstimateOptions {
  std::string command; // "invert" or "estimate"
  std::string method;  // plugin name
  std::string model;   // estimate only
  std::string case_name;
  std::string data;
  std::string out, plot, json;
  bool stream = false;
  std::vector<std::string> options; // --option KEY=VALUE passed to the plugin
  // --set: values of the model (estimate) or, the older spelling of --option, method options
  // (invert; estimate when KEY is one of the method's options)
  std::vector<std::string> sets;
  EstimatorSettings settings;
};

std::string cell(double v) {
  return std::isnan(v) ? std::string() : fmt::format("{:.9g}", v);
}

std::string csv_header(const std::vector<std::string>& columns) {
  std::vector<std::string> fields{"time"};
  fields.insert(fields.end(), columns.begin(), columns.end());
  return csv_line(fields);
}

std::string csv_row(const EstimateRow& r) {
  std::string s = fmt::format("{:.10g}", r.time);
  for (double v : r.values)
    s += "," + cell(v);
  return s + "\n";
}

// Re-anchors a CsvError from parsing "header\nline" to the line's real number in the stream.
lang::CsvError at_line(const lang::CsvError& e, std::size_t line) {
  std::string what = e.what();
  std::string prefix = e.column == 0 ? fmt::format("<stdin>:{}: ", e.row)
                                     : fmt::format("<stdin>:{}:{}: ", e.row, e.column);
  std::string msg = what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what;
  return lang::CsvError("<stdin>", line, e.column, msg);
}

std::string plot_svg(const std::string& title, const std::vector<std::string>& out_columns,
                     const std::vector<EstimateRow>& rows, const lang::CsvTable* data) {
  plot::Panel panel;
  panel.title = title;
  panel.y_label = "temperature [degC]";
  panel.x_is_time_s = true;
  for (std::size_t c = 0; c < out_columns.size(); ++c) {
    const std::string& name = out_columns[c];
    if (name.rfind("sd_", 0) == 0 || name.rfind("q_", 0) == 0 || name == "tau_hat" ||
        name == "xi_hat" || (name.size() > 4 && name.substr(name.size() - 4) == "_err"))
      continue;
    plot::Series s;
    s.label = name + " (estimate)";
    if (name.size() > 5 && name.substr(name.size() - 5) == "_true") {
      s.label = name;
      s.style = plot::LineStyle::dashed;
    }
    for (const auto& r : rows) {
      s.x.push_back(r.time);
      s.y.push_back(r.values[c]);
    }
    panel.series.push_back(std::move(s));
  }
  if (data) { // measured columns as markers (thinned to about 400 points)
    std::size_t stride = std::max<std::size_t>(1, data->rows() / 400);
    for (std::size_t c = 1; c < data->columns.size(); ++c) {
      plot::Series s;
      s.label = data->columns[c] + " (data)";
      s.style = plot::LineStyle::markers;
      for (std::size_t k = 0; k < data->rows(); k += stride) {
        s.x.push_back(data->time()[k]);
        s.y.push_back(data->cells[c][k]);
      }
      panel.series.push_back(std::move(s));
    }
  }
  plot::Figure fig;
  fig.panels.push_back(std::move(panel));
  return plot::render_svg(fig);
}

/// Prints the metrics to standard error; returns the JSON report (--json) or "".
std::string report(const EstimateOptions& o, const Estimator& est) {
  auto metrics = est.metrics();
  for (const auto& m : metrics)
    std::cerr << fmt::format("thermnet {}: {} = {:.6g}{}{}\n", o.command, m.name, m.value,
                             m.unit.empty() ? "" : " ", m.unit);
  if (o.json.empty()) return {};
  nlohmann::json j;
  j["method"] = o.method;
  j["options"] = o.settings.values();
  nlohmann::json mj = nlohmann::json::object(), units = nlohmann::json::object();
  for (const auto& m : metrics) {
    mj[m.name] = m.value;
    units[m.name] = m.unit;
  }
  j["metrics"] = mj;
  j["units"] = units;
  return j.dump(2) + "\n";
}

/// Counts the rows that carry an estimate (a value that is not NaN).
class EstimateCount {
public:
  /// Counts `r` if it has a value.
  void add(const EstimateRow& r) {
    if (std::any_of(r.values.begin(), r.values.end(), [](double v) { return !std::isnan(v); }))
      ++rows_;
  }
  /// Throws EstimatorError when no row had one: an empty result must not pass as success.
  void require_some(const EstimateOptions& o, std::size_t rows_read) const {
    if (rows_ == 0)
      throw EstimatorError(fmt::format(
          "{} produced no estimate from {} data row{}; see its options (thermnet {} --help)",
          o.method, rows_read, rows_read == 1 ? "" : "s", o.command));
  }

private:
  std::size_t rows_ = 0;
};

int run_stream(EstimateOptions& o, EstimatorContext& ctx, const EstimatorPlugin& plugin) {
  std::string header;
  std::size_t line_no = 0;
  while (std::getline(std::cin, header)) {
    ++line_no;
    if (header.find_first_not_of(" \t\r") != std::string::npos) break;
  }
  lang::CsvTable head;
  try {
    head = lang::parse_csv(header, "<stdin>");
    lang::check_celsius_columns(head);
  } catch (const lang::CsvError& e) {
    throw at_line(e, line_no);
  }
  ctx.columns = head.columns;
  auto est = plugin.create(ctx);
  // Each row is flushed as it is estimated, and a failed write ends the run.
  auto emit = [&](const std::vector<EstimateRow>& rows, EstimateCount& count) {
    for (const auto& r : rows) {
      std::cout << csv_row(r);
      count.add(r);
    }
    flush_standard_output();
  };
  std::cout << csv_header(est->output_columns());
  flush_standard_output();
  EstimateCount count;
  std::size_t rows_read = 0;
  std::string line;
  double last_time = -std::numeric_limits<double>::infinity();
  while (std::getline(std::cin, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    lang::CsvTable t;
    try {
      t = lang::parse_csv(header + "\n" + line, "<stdin>");
      lang::check_celsius_columns(t);
    } catch (const lang::CsvError& e) {
      throw at_line(e, line_no);
    }
    std::vector<double> row(t.columns.size());
    for (std::size_t c = 0; c < row.size(); ++c)
      row[c] = t.cells[c][0];
    if (!(row[0] > last_time))
      throw lang::CsvError(
          "<stdin>", line_no, 1,
          fmt::format("time {:g} does not increase (previous row: {:g})", row[0], last_time));
    last_time = row[0];
    ++rows_read;
    emit(est->push(row), count);
  }
  emit(est->finish(), count);
  const std::string json = report(o, *est);
  count.require_some(o, rows_read);
  if (!json.empty()) write_output_file(o.json, json);
  return exit_ok;
}

int run_batch(EstimateOptions& o, EstimatorContext& ctx, const EstimatorPlugin& plugin,
              const std::string& title) {
  lang::CsvTable table = lang::read_csv(o.data);
  lang::check_celsius_columns(table);
  if (table.rows() == 0) throw lang::CsvError(o.data, 2, 0, "the file has no data rows");
  ctx.columns = table.columns;
  auto est = plugin.create(ctx);
  const auto columns = est->output_columns();
  // The CSV goes out row by row; the rows are kept only for a plot.
  auto csv = open_output(o.out);
  csv->write(csv_header(columns));
  std::vector<EstimateRow> kept;
  EstimateCount count;
  auto emit = [&](std::vector<EstimateRow> rows) {
    for (auto& r : rows) {
      csv->write(csv_row(r));
      count.add(r);
      if (!o.plot.empty()) kept.push_back(std::move(r));
    }
  };
  std::vector<double> row(table.columns.size());
  for (std::size_t k = 0; k < table.rows(); ++k) {
    for (std::size_t c = 0; c < row.size(); ++c)
      row[c] = table.cells[c][k];
    emit(est->push(row));
  }
  emit(est->finish());
  const std::string json = report(o, *est);
  count.require_some(o, table.rows());
  std::unique_ptr<OutputStream> svg, json_out;
  if (!o.plot.empty()) {
    svg = std::make_unique<OutputStream>(o.plot);
    svg->write(plot_svg(title, columns, kept, &table));
  }
  if (!json.empty()) {
    json_out = std::make_unique<OutputStream>(o.json);
    json_out->write(json);
  }
  commit({csv.get(), svg.get(), json_out.get()});
  return exit_ok;
}

/// True when `name` is one of the plugin's documented options.
bool is_method_option(const EstimatorPlugin& plugin, const std::string& name) {
  return std::any_of(plugin.options.begin(), plugin.options.end(),
                     [&](const EstimatorOption& opt) { return opt.name == name; });
}

int run_method(EstimateOptions& o, lang::SourceManager& sources) {
  const std::string who = "thermnet " + o.command;
  const EstimatorPlugin* plugin = EstimatorRegistry::global().find(o.method);
  bool wants_model = o.command == "estimate";
  // Method options; in `estimate`, --set items that name none of them are values of the model.
  std::vector<std::string> model_sets;
  for (const auto& [flag, items] : {std::pair{"--option", &o.options}, std::pair{"--set", &o.sets}})
    for (const auto& kv : *items) {
      auto eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) {
        std::cerr << who << ": error: " << flag << " expects KEY=VALUE, got '" << kv << "'\n";
        return exit_usage;
      }
      const std::string key = kv.substr(0, eq);
      if (wants_model && items == &o.sets && !(plugin && is_method_option(*plugin, key)))
        model_sets.push_back(kv);
      else
        o.settings.set(key, kv.substr(eq + 1));
    }
  if (!plugin || plugin->needs_model != wants_model) {
    std::string names;
    for (const auto& n : EstimatorRegistry::global().names()) {
      const auto* p = EstimatorRegistry::global().find(n);
      if (p->needs_model == wants_model) names += (names.empty() ? "" : ", ") + n;
    }
    std::cerr << fmt::format("{}: error: unknown method '{}' (available: {})\n", who, o.method,
                             names);
    return exit_usage;
  }
  // Every option given must be one of the method's: a misspelt one would be ignored.
  for (const auto& [key, value] : o.settings.values()) {
    if (is_method_option(*plugin, key)) continue;
    std::vector<std::string> known;
    for (const auto& opt : plugin->options)
      known.push_back(opt.name);
    std::string msg = fmt::format("{}: error: method '{}' has no option '{}'", who, o.method, key);
    if (auto s = lang::closest_match(key, known))
      msg += fmt::format("; did you mean '{}'?", *s);
    else
      msg += fmt::format(" (its options: {})", fmt::join(known, ", "));
    std::cerr << msg << "\n";
    return exit_usage;
  }
  if (o.stream && !o.out.empty()) {
    std::cerr << who << ": error: --stream writes to standard output; drop -o\n";
    return exit_usage;
  }
  if (o.stream && !o.plot.empty()) {
    std::cerr << who << ": error: --plot needs the whole record; not with --stream\n";
    return exit_usage;
  }
  if (o.stream && !o.data.empty() && o.data != "-") {
    std::cerr << who << ": error: --stream reads standard input; give DATA as '-' or omit it\n";
    return exit_usage;
  }
  // A DATA file named on the command line is the user's choice: readable wherever it lies.
  if (!o.data.empty() && o.data != "-") lang::allow_named_path(o.data);
  std::unique_ptr<lang::Model> model;
  std::optional<lang::NetworkSpec> spec;
  EstimatorContext ctx;
  ctx.settings = o.settings;
  std::string title = fmt::format("{} ({})", o.method, o.data.empty() ? "stdin" : o.data);
  if (wants_model) {
    int status = exit_ok;
    model = load_checked_model(o.model, sources, status, model_sets);
    if (!model) return status;
    for (const auto& p : model->params())
      for (const auto& kv : o.sets)
        if (kv.rfind(p.name + "=", 0) == 0 && is_method_option(*plugin, p.name)) {
          std::cerr << fmt::format("{}: error: --set {}: '{}' is both a param of the model and "
                                   "an option of method '{}': write --option for the method "
                                   "(a param of that name cannot be set here)\n",
                                   who, kv, p.name, o.method);
          return exit_usage;
        }
    spec = model->instantiate(o.case_name);
    ctx.network = &*spec;
    if (o.data.empty() && !o.stream) o.data = spec->settings.data_path;
    if (o.data.empty() && !o.stream) {
      std::cerr << who << ": error: no DATA file given and the case has no 'data'\n";
      return exit_usage;
    }
    title = fmt::format("{} — {} — case {}", o.method, model->name(), spec->settings.name);
  } else if (o.data.empty() && !o.stream) {
    std::cerr << who << ": error: give a DATA file, or --stream to read standard input\n";
    return exit_usage;
  }
  std::vector<NamedInput> inputs = model ? model_inputs(*model) : std::vector<NamedInput>{};
  if (!o.data.empty() && o.data != "-") inputs.push_back({o.data, "the data file"});
  check_outputs({{"-o", o.out}, {"--plot", o.plot}, {"--json", o.json}}, inputs);
  return o.stream ? run_stream(o, ctx, *plugin) : run_batch(o, ctx, *plugin, title);
}

int run(EstimateOptions& o) {
  return run_command("thermnet " + o.command,
                     [&](lang::SourceManager& sources) { return run_method(o, sources); });
}

// An option that stores its text in the plugin settings under `key`.
CLI::Option* setting(CLI::App* cmd, const std::shared_ptr<EstimateOptions>& o,
                     const std::string& flag, const std::string& key, const std::string& doc) {
  return cmd->add_option_function<std::string>(
      flag, [o, key](const std::string& v) { o->settings.set(key, v); }, doc);
}

std::string methods_doc(bool model) {
  std::string s;
  for (const auto& n : EstimatorRegistry::global().names()) {
    const auto* p = EstimatorRegistry::global().find(n);
    if (p->needs_model != model) continue;
    s += fmt::format("\n  {}: {}", n, p->doc);
    for (const auto& opt : p->options)
      s += fmt::format("\n      {}{}: {}", opt.name,
                       opt.default_value.empty() ? "" : " (" + opt.default_value + ")", opt.doc);
  }
  return s;
}

void add_common(CLI::App* cmd, const std::shared_ptr<EstimateOptions>& o) {
  cmd->add_option("-o,--out", o->out, "CSV of estimates (default: standard output)")
      ->check(output_file_validator());
  cmd->add_option("--plot", o->plot, "SVG plot of estimates and data against time")
      ->check(output_file_validator());
  cmd->add_option("--json", o->json, "JSON report: method, options, metrics")
      ->check(output_file_validator());
  cmd->add_flag("--stream", o->stream,
                "read rows from standard input, write the estimate of each row as it arrives");
  cmd->add_option("--option", o->options, "any method option as KEY=VALUE (repeatable)")
      ->type_name("KEY=VALUE");
  if (o->command == "estimate")
    add_set_option(cmd, o->sets,
                   "; a KEY that is one of the method's options is passed to the method, as "
                   "with --option");
  else
    cmd->add_option("--set", o->sets, "the same as --option (repeatable)")->type_name("KEY=VALUE");
}

} // namespace

void add_estimate_commands(CLI::App& app, int& status) {
  {
    auto o = std::make_shared<EstimateOptions>();
    o->command = "invert";
    o->method = "tim-ab";
    CLI::App* cmd = app.add_subcommand(
        "invert", "Inverse estimation from sensor data alone (TIM-AB surface temperature)");
    cmd->footer("Methods and their options (--option KEY=VALUE):" + methods_doc(false) +
                "\nSee docs/inverse.md.");
    cmd->add_option("DATA", o->data, "CSV: time, sensor columns ('-' or omitted with --stream)");
    cmd->add_option("--method", o->method, "inverse method (default: tim-ab)");
    setting(cmd, o, "--sensors", "sensors", "sensor columns B,C,D, nearest the surface first");
    setting(cmd, o, "--true", "true", "column with the true value at A (adds errors)");
    setting(cmd, o, "--target", "target", "name of the estimated point (default: A)");
    setting(cmd, o, "--mode", "mode", "realtime (sliding window) or full (one fit)")
        ->check(CLI::IsMember({"realtime", "full"}));
    setting(cmd, o, "--tau", "tau", "thermal hysteresis time tau, s")->check(CLI::PositiveNumber);
    setting(cmd, o, "--eta", "eta", "window length t_w = eta tau (default 4)")
        ->check(CLI::PositiveNumber);
    setting(cmd, o, "--window", "window", "window length in s (instead of --eta/--tau)")
        ->check(CLI::PositiveNumber);
    setting(cmd, o, "--slide", "slide", "slide step n_s, samples (default 10)")
        ->check(CLI::Range(1, 1000000000));
    setting(cmd, o, "--filter", "filter", "noise filter: none, savgol, gaussian, moving-average")
        ->check(CLI::IsMember({"none", "savgol", "gaussian", "moving-average"}));
    setting(cmd, o, "--gamma", "gamma", "filter window / inversion window (default 0.5)")
        ->check(CLI::Range(1e-6, 1.0));
    setting(cmd, o, "--order", "order", "Savitzky-Golay order (default 3)")
        ->check(CLI::Range(0, 12));
    add_common(cmd, o);
    cmd->callback([o, &status] { status = run(*o); });
  }
  {
    auto o = std::make_shared<EstimateOptions>();
    o->command = "estimate";
    o->method = "ekf";
    CLI::App* cmd = app.add_subcommand(
        "estimate",
        "State estimation over a model (digital twin): hidden nodes and an unknown heat input");
    cmd->footer("Methods and their options (--option KEY=VALUE):" + methods_doc(true) +
                "\nSee docs/inverse.md.");
    cmd->add_option("MODEL", o->model, "model file (.tnet)")->required();
    cmd->add_option("DATA", o->data,
                    "CSV of measurements (default: the case's data; '-' with --stream)");
    cmd->add_option("--case", o->case_name, "case whose inputs drive the model");
    cmd->add_option("--method", o->method, "estimator (default: ekf)");
    setting(cmd, o, "--measured", "measured", "measured columns (default: every node column)");
    setting(cmd, o, "--estimate-input", "input", "node with an unknown heat input to estimate");
    cmd->add_flag_function(
        "--smooth", [o](std::int64_t) { o->settings.set("smooth", "yes"); },
        "Rauch-Tung-Striebel smoother over the whole record (not with --stream)");
    setting(cmd, o, "--sigma-meas", "sigma-meas", "sensor standard deviation, K (default 0.1)")
        ->check(CLI::PositiveNumber);
    setting(cmd, o, "--process-noise", "process", "process noise, K/sqrt(s) (default 0.01)")
        ->check(CLI::NonNegativeNumber);
    setting(cmd, o, "--input-noise", "input-noise",
            "random-walk rate of the unknown input, W/sqrt(s) (default 0.05)")
        ->check(CLI::NonNegativeNumber);
    setting(cmd, o, "--sigma0", "sigma0", "initial standard deviation, K (default 2)")
        ->check(CLI::PositiveNumber);
    add_common(cmd, o);
    cmd->callback([o, &status] {
      if (o->stream && o->settings.flag("smooth")) {
        std::cerr << "thermnet estimate: error: --smooth needs the whole record; not with "
                     "--stream\n";
        status = exit_usage;
        return;
      }
      status = run(*o);
    });
  }
}

} // namespace thermnet::cli
