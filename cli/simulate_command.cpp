#include "cli/simulate_command.hpp"

#include "app/energy_report.hpp"
#include "app/exit_status.hpp"
#include "app/heat_flow_report.hpp"
#include "app/model_loading.hpp"
#include "app/node_summary.hpp"
#include "app/option_rules.hpp"
#include "app/output_stream.hpp"
#include "app/param_overrides.hpp"
#include "app/requirement_report.hpp"
#include "app/result_output.hpp"
#include "app/uncertainty.hpp"
#include "cli/run_command.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>

#include <iostream>
#include <memory>
#include <optional>

namespace thermnet::cli {
using namespace app;
namespace {

struct SimulateOptions {
  std::string model;
  std::string case_name;
  bool steady = false;
  bool sensors = false;
  std::string duration;
  std::string output_interval;
  std::string out;
  std::string plot;
  std::vector<std::string> nodes;
  std::string unit = "degC";
  std::string flows;
  std::vector<std::string> elements;
  std::string energy;
  std::string summary;
  std::string band;
  std::vector<std::string> sets;
  std::string json;
  bool stats = false;
  double rtol = 1e-6;
  double atol = 1e-6;
  std::string linear_solver = "auto";
  std::size_t samples = 0; // > 0: uncertainty bands (app/uncertainty.hpp)
  std::uint64_t seed = 1;
  std::vector<double> percentiles{5, 50, 95};
  int threads = 0;
};

/// Writes a CSV known in full (to standard output without -o) and the plot, if there is one, as
/// one unit.
void write_outputs(const SimulateOptions& o, const std::string& csv, const std::string& svg) {
  auto csv_out = open_output(o.out);
  csv_out->write(csv);
  std::unique_ptr<OutputStream> svg_out;
  if (!o.plot.empty()) {
    svg_out = std::make_unique<OutputStream>(o.plot);
    svg_out->write(svg);
  }
  commit({csv_out.get(), svg_out.get()});
}

/// `--samples N`: bands over N draws of the ranged params instead of one run.
void run_samples(const lang::Model& model, const SimulateOptions& o, const SimulationOptions& sim) {
  UncertaintyOptions u;
  u.samples = o.samples;
  u.seed = o.seed;
  u.percentiles = o.percentiles;
  u.threads = o.threads;
  u.simulation = sim;
  UncertaintyBands b = run_uncertainty(model, o.case_name, u);
  std::cerr << fmt::format("thermnet simulate: {} samples of {} ranged params, {} failed\n",
                           b.samples, b.params.size(), b.failed);
  std::string svg;
  if (!o.plot.empty())
    svg = plot_bands_svg(b, o.nodes,
                         fmt::format("{} — case {}, {} samples", model.name(),
                                     model.resolve_case(o.case_name), b.samples));
  write_outputs(o, format_bands_csv(b), svg);
}

LinearSolverKind solver_kind(const std::string& s) {
  if (s == "dense") return LinearSolverKind::dense;
  if (s == "klu") return LinearSolverKind::klu;
  if (s == "krylov") return LinearSolverKind::krylov;
  return LinearSolverKind::automatic;
}

void print_stats(const SolverStats& s, double wall) {
  std::cerr << fmt::format(
      "thermnet: {} with {} linear solver: {} steps, {} rhs evaluations, {} Jacobians, "
      "{} linear setups, {} Newton iterations ({} failed), {} linear iterations, "
      "{} preconditioner setups, {} error test failures, {} events, {} restarts, {:.3f} s wall\n",
      s.integrator, s.linear_solver, s.steps, s.rhs_evals, s.jac_evals, s.linear_setups,
      s.nonlinear_iters, s.nonlinear_fails, s.linear_iters, s.prec_setups, s.error_test_fails,
      s.events, s.restarts, wall);
}

/// The unit trap of inputs: `P1 * table("in.csv", "Q1")` with P1 in W/% and the column in
/// percent, but no [%] after the table, puts 100 times the power into a node, which reaches
/// thousands of degC. Such temperatures in a model where nothing is that hot to begin with (no
/// boundary or start above kHot) are most likely such a mistake: the run says so (a note on
/// standard error; the results are written as computed).
class PlausibleHeat {
public:
  /// The hottest temperature the model prescribes: boundaries (as the rows show them) and starts.
  explicit PlausibleHeat(const lang::NetworkSpec& spec) : spec_(spec) {
    for (const auto& n : spec.nodes)
      if (n.T0) prescribed_ = std::max(prescribed_, *n.T0);
    if (spec.settings.initial) prescribed_ = std::max(prescribed_, *spec.settings.initial);
  }
  /// Takes one output row (K, the spec's nodes first).
  void add(double t, const std::vector<double>& temps) {
    for (std::size_t i = 0; i < spec_.nodes.size() && i < temps.size(); ++i) {
      if (spec_.nodes[i].boundary) {
        prescribed_ = std::max(prescribed_, temps[i]);
      } else if (temps[i] > hottest_) {
        hottest_ = temps[i];
        node_ = i;
        time_ = t;
      }
    }
  }
  /// The note, or empty when the temperatures are plausible.
  std::string note() const {
    if (!(hottest_ > kHot) || prescribed_ > kHot) return {};
    return fmt::format("node '{}' reaches {:.0f} degC (t = {:g} s), though no boundary or start "
                       "temperature of the model is above {:.0f} degC: are the inputs in the "
                       "units they are read in? (a table's values are bare unless a unit follows "
                       "it: table(\"in.csv\", \"Q\") [%])",
                       spec_.nodes[node_].name, hottest_ - lang::kZeroCelsius, time_,
                       kHot - lang::kZeroCelsius);
  }

private:
  static constexpr double kHot = 1000.0 + lang::kZeroCelsius; // K
  const lang::NetworkSpec& spec_;
  double prescribed_ = 0.0;
  double hottest_ = 0.0;
  std::size_t node_ = 0;
  double time_ = 0.0;
};

int run_simulate(const SimulateOptions& o, lang::SourceManager& sources) {
  int status = exit_ok;
  auto model = load_checked_model(o.model, sources, status, o.sets);
  if (!model) return status;
  check_outputs({{"-o", o.out},
                 {"--plot", o.plot},
                 {"--flows", o.flows},
                 {"--energy", o.energy},
                 {"--summary", o.summary},
                 {"--json", o.json}},
                model_inputs(*model));
  if (o.samples > 0 && !(o.flows.empty() && o.energy.empty() && o.summary.empty()))
    throw std::invalid_argument(
        "--flows, --energy and --summary report one run: not with --samples");
  if (o.steady && !o.energy.empty())
    throw std::invalid_argument("--energy reports a transient: not with --steady");
  if (!o.band.empty() && o.summary.empty())
    throw std::invalid_argument("--band is reported in --summary FILE: give --summary too");
  SimulationOptions sim;
  if (!o.duration.empty()) sim.duration = parse_time(o.duration);
  if (!o.output_interval.empty()) sim.output = parse_time(o.output_interval);
  sim.steady = o.steady;
  sim.sensors = o.sensors;
  sim.solver.rtol = o.rtol;
  sim.solver.atol = o.atol;
  sim.solver.linear_solver = solver_kind(o.linear_solver);
  if (o.samples > 0) {
    run_samples(*model, o, sim);
    return exit_ok;
  }
  // The case's network elaborated by the check (or with the --set values) is taken, not built
  // again.
  Network net(model->take_network(o.case_name));
  // The network owns all it needs: the syntax trees go before the run, so that the solver reuses
  // their memory instead of touching new pages (a 100,000-node model's trees are hundreds of MB).
  const std::string model_name = model->name();
  model.reset();
  const lang::NetworkSpec& spec = net.spec();
  // The model's requirements are checked on every transient and reported on standard error.
  std::optional<RequirementCheck> check;
  if (!o.steady && !spec.requirements.empty()) check.emplace(spec);
  std::vector<std::string> names, element_names;
  for (const auto& n : spec.nodes)
    names.push_back(n.name);
  if (o.sensors) // their readings follow the nodes in every row (SimulationOptions::sensors)
    for (int e : net.sensor_elements())
      names.push_back(spec.elements[static_cast<std::size_t>(e)].name);
  for (const auto& e : spec.elements)
    element_names.push_back(e.name);
  // Everything selected is checked before the run: the CSV goes out row by row, only the plotted
  // columns are kept for the plot.
  const std::vector<std::size_t> columns = plot_columns(names, o.nodes);
  std::vector<std::size_t> flow_elements =
      select_names(element_names, o.elements, "--elements", "element");
  std::erase_if(flow_elements, [&](std::size_t e) { // a sensor carries no heat
    return spec.elements[e].schema && spec.elements[e].schema->observes;
  });
  const bool kelvin = o.unit == "K";
  std::optional<NodeSummary> summary;
  if (!o.summary.empty())
    summary.emplace(names, columns,
                    o.band.empty() ? std::optional<Band>{}
                                   : std::optional<Band>{parse_band(o.band)});
  SimulationResult kept;
  if (!o.plot.empty())
    for (std::size_t c : columns)
      kept.names.push_back(names[c]);
  std::vector<std::string> selected;
  for (std::size_t c : columns)
    selected.push_back(names[c]);
  auto csv = open_output(o.out);
  csv->write(result_csv_header(selected));
  std::unique_ptr<OutputStream> flows;
  if (!o.flows.empty()) {
    flows = std::make_unique<OutputStream>(o.flows);
    if (!o.steady) flows->write(flow_csv_header(spec, flow_elements));
  }
  std::vector<std::vector<double>> heat;
  std::vector<double> unknowns(static_cast<std::size_t>(net.size())), row_temps;
  EnergyTotals energy;
  std::optional<nlohmann::json> json;
  if (!o.json.empty())
    json = nlohmann::json{{"model", model_name},
                          {"case", spec.settings.name},
                          {"unit", kelvin ? "K" : "degC"},
                          {"nodes", selected},
                          {"flow_columns", flow_columns(spec, flow_elements)},
                          {"times", nlohmann::json::array()},
                          {"temperatures", nlohmann::json::array()},
                          {"flows", nlohmann::json::array()}};
  PlausibleHeat heat_check(spec);
  auto start = std::chrono::steady_clock::now();
  const auto row = [&](double t, const std::vector<double>& temps) {
    heat_check.add(t, temps);
    row_temps.clear();
    for (std::size_t c : columns)
      row_temps.push_back(temps[c]);
    csv->write(result_csv_row(t, row_temps, kelvin));
    if (summary) summary->add(t, temps);
    if (flows || json || (check && check->needs_heat())) {
      for (std::size_t u = 0; u < net.unknown_nodes().size(); ++u)
        unknowns[u] = temps[static_cast<std::size_t>(net.unknown_nodes()[u])];
      net.element_heat(t, unknowns.data(), heat);
    }
    if (check) check->add(t, temps, heat);
    if (flows)
      flows->write(o.steady ? steady_flow_listing(spec, flow_elements, heat, temps)
                            : flow_csv_row(t, spec, flow_elements, heat));
    if (json) {
      (*json)["times"].push_back(t);
      nlohmann::json row = nlohmann::json::array();
      for (double T : row_temps)
        row.push_back(kelvin ? T : T - lang::kZeroCelsius);
      (*json)["temperatures"].push_back(std::move(row));
      (*json)["flows"].push_back(flow_values(spec, flow_elements, heat));
    }
    if (o.plot.empty()) return;
    kept.times.push_back(t);
    kept.temps.push_back(row_temps);
  };
  const SolverStats stats = simulate(net, sim, row, o.energy.empty() ? nullptr : &energy);
  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (o.stats) print_stats(stats, wall);
  if (const std::string note = heat_check.note(); !note.empty())
    std::cerr << "thermnet simulate: note: " << note << "\n";
  if (check) {
    const auto outcomes = check->outcomes();
    std::cerr << outcomes_text(outcomes, sources)
              << fmt::format("thermnet simulate: {} of {} requirements violated (`thermnet check` "
                             "exits 1 on a violation)\n",
                             violations(outcomes), outcomes.size());
  }
  std::unique_ptr<OutputStream> svg;
  if (!o.plot.empty()) {
    svg = std::make_unique<OutputStream>(o.plot);
    svg->write(
        plot_result_svg(kept, fmt::format("{} — case {}", model_name, net.spec().settings.name)));
  }
  std::unique_ptr<OutputStream> energy_out, summary_out;
  if (!o.energy.empty()) {
    energy_out = std::make_unique<OutputStream>(o.energy);
    energy_out->write(energy_report(spec, energy));
  }
  if (summary) {
    summary_out = std::make_unique<OutputStream>(o.summary);
    summary_out->write(summary->csv(kelvin));
  }
  std::unique_ptr<OutputStream> json_out;
  if (json) {
    json_out = std::make_unique<OutputStream>(o.json);
    json_out->write(json->dump(1) + "\n");
  }
  commit({csv.get(), svg.get(), flows.get(), energy_out.get(), summary_out.get(), json_out.get()});
  return exit_ok;
}

} // namespace

void add_simulate_command(CLI::App& app, int& status) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a case: temperatures over time as CSV");
  cmd->add_option("MODEL", o->model, "model file (.tnet)")->required();
  cmd->add_option("--case", o->case_name, "case to run (default: the only case, or 'default')");
  cmd->add_flag("--steady", o->steady,
                "solve the steady state (inputs at t = 0), one row at time 0");
  cmd->add_option("--duration", o->duration,
                  "simulated time, e.g. 2500, 3h, 45min (overrides the case)");
  cmd->add_option("--output", o->output_interval,
                  "output interval, e.g. 10, 1min (default: duration/1000)");
  cmd->add_option("-o,--out", o->out, "CSV output file (default: standard output)")
      ->check(output_file_validator());
  cmd->add_option("--plot", o->plot, "SVG plot of node temperatures against time")
      ->check(output_file_validator());
  cmd->add_flag("--sensors", o->sensors,
                "add each sensor's reading as a column named after the sensor (select them with "
                "--nodes like nodes)");
  cmd->add_option("--nodes", o->nodes,
                  "nodes and boundaries in the CSV, plot and summary: names or globs "
                  "(comma-separated; default: all)")
      ->delimiter(',');
  add_set_option(cmd, o->sets, "; with --samples, the ranged params are still drawn");
  cmd->add_option("--unit", o->unit, "temperature unit of the CSV and summary (default degC)")
      ->check(CLI::IsMember({"degC", "K"}));
  cmd->add_option("--flows", o->flows,
                  "heat flows, W: a CSV over time (two-terminal elements: from the first node to "
                  "the second; others: NAME@NODE, heat into the node); with --steady, a listing "
                  "per node with the balance residual");
  cmd->add_option("--elements", o->elements,
                  "elements in --flows: names or globs (comma-separated; default: all)")
      ->delimiter(',');
  cmd->add_option("--energy", o->energy,
                  "energy balance over the run: per node stored, from sources, through links; "
                  "per boundary received; per source energy, on time, duty, switches");
  cmd->add_option("--summary", o->summary,
                  "CSV per node: min, max and their times, time-weighted mean (and --band)");
  cmd->add_option("--json", o->json,
                  "the run as JSON: model, case, unit, nodes, times, temperatures[row][node], "
                  "flow_columns and flows[row][column] (W, as --flows; --elements selects)")
      ->check(output_file_validator());
  cmd->add_option("--band", o->band,
                  "LO..HI in degC: --summary adds the time each node spends outside it");
  cmd->add_flag("--stats", o->stats, "print solver statistics to standard error");
  cmd->add_option("--rtol", o->rtol, "relative tolerance")
      ->check(rule_validator(relative_tolerance_rule, "NUMBER"));
  cmd->add_option("--atol", o->atol, "absolute tolerance, K")
      ->check(rule_validator(absolute_tolerance_rule, "NUMBER"));
  cmd->add_option("--linear-solver", o->linear_solver, "linear solver")
      ->check(CLI::IsMember({"auto", "dense", "klu", "krylov"}));
  cmd->add_option("--samples", o->samples,
                  "uncertainty bands: draw the ranged params uniformly N times; the CSV gets "
                  "NODE_min, NODE_pQ..., NODE_max columns");
  cmd->add_option("--seed", o->seed, "random seed of --samples (same seed, same bands)");
  cmd->add_option("--percentiles", o->percentiles, "percentiles of --samples (default 5,50,95)")
      ->delimiter(',');
  cmd->add_option("--threads", o->threads, "worker threads of --samples (0: all cores)")
      ->check(rule_validator(non_negative_whole_rule, "INT"));
  // Its std::invalid_argument errors come from its options (times, --nodes, --percentiles): usage.
  cmd->callback([o, &status] {
    status = run_command(
        "thermnet simulate",
        [&](lang::SourceManager& sources) { return run_simulate(*o, sources); }, exit_usage);
  });
}

} // namespace thermnet::cli
