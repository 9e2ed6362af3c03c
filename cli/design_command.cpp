// `thermnet design MODEL`: the ranged params (the design variables) chosen so that the model's
// requirements hold in every case at the least heater energy (or installed power), by
// design_search; reports the values, the requirements at the chosen point, each source's power,
// energy and duty, writes the designed model (-o), a JSON report and a plot of the controlled
// nodes with their bands.

#include "cli/design_command.hpp"

#include "app/design_search.hpp"
#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "app/option_rules.hpp"
#include "app/output_files.hpp"
#include "app/param_overrides.hpp"
#include "app/requirement_report.hpp"
#include "app/result_output.hpp"
#include "cli/run_command.hpp"
#include "lang/evaluator.hpp"
#include "lang/rewrite/model_files.hpp"
#include "lang/units.hpp"
#include "plot/svg_plot.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <iostream>
#include <set>

namespace thermnet::cli {
using namespace app;
namespace {

struct DesignOptions {
  std::string model;
  std::vector<std::string> params;
  std::vector<std::string> sets;
  std::vector<std::string> cases;
  std::string objective = "energy";
  std::size_t samples = 0;
  std::size_t evaluations = 300;
  std::uint64_t seed = 1;
  int threads = 0;
  std::string out;
  std::string json;
  std::string plot;
};

/// A param value in its dimension's unit (absolute temperatures in degC).
std::string show(const lang::ParamInfo& p, double si) {
  if (!p.dim) return fmt::format("{:.4g}", si);
  return lang::format_value(si, *p.dim, *p.dim == lang::dim::temperature);
}

/// The ranged params to design: those named by --param, else every ranged param.
std::vector<lang::ParamInfo> design_params(const lang::Model& model,
                                           const std::vector<std::string>& names) {
  std::vector<lang::ParamInfo> all = model.params(), out;
  std::vector<std::string> ranged;
  for (const auto& p : all)
    if (p.ranged()) ranged.push_back(p.name);
  for (const auto& n : names) {
    auto it = std::find_if(all.begin(), all.end(), [&](const auto& p) { return p.name == n; });
    if (it == all.end() || !it->ranged()) {
      std::string msg = fmt::format("--param '{}' is not a ranged param of the model", n);
      if (auto near = lang::closest_match(n, ranged))
        msg += fmt::format("; did you mean '{}'?", *near);
      throw std::invalid_argument(msg);
    }
  }
  for (const auto& p : all)
    if (p.ranged() &&
        (names.empty() || std::find(names.begin(), names.end(), p.name) != names.end()))
      out.push_back(p);
  return out;
}

/// Each source's installed power, energy, on time, duty and switches in every run.
std::string sources_table(const std::vector<CheckedRun>& runs, nlohmann::json& json) {
  std::string s;
  json = nlohmann::json::array();
  for (const auto& r : runs) {
    const auto& spec = r.net->spec();
    const double span = r.energy.t1 - r.energy.t0;
    s += fmt::format("sources, case {} ({:g} s):\n  {:<12} {:>10} {:>12} {:>12} {:>7} {:>9}\n",
                     spec.settings.name, span, "source", "P [W]", "energy [J]", "on time [s]",
                     "duty", "switches");
    double total = 0.0;
    for (std::size_t e = 0; e < spec.elements.size(); ++e) {
      const auto& el = spec.elements[e];
      if (el.nodes().size() != 1 || el.composite() != lang::Composite::none) continue;
      const double energy = r.energy.element_energy[e][0];
      const double on = r.energy.on_time[e];
      const double duty = span > 0 ? on / span : 0.0;
      const bool constant_p = el.has("P") && el.values.at("P").is_constant();
      total += energy;
      s += fmt::format("  {:<12} {:>10} {:>12.6g} {:>12.6g} {:>6.1f}% {:>9}\n", el.name,
                       constant_p ? fmt::format("{:.4g}", el.number("P")) : "-", energy, on,
                       100 * duty, r.energy.switches[e]);
      json.push_back({{"case", spec.settings.name},
                      {"source", el.name},
                      {"P", constant_p ? nlohmann::json(el.number("P")) : nlohmann::json()},
                      {"energy", energy},
                      {"on_time", on},
                      {"duty", duty},
                      {"switches", r.energy.switches[e]}});
    }
    s += fmt::format("  total energy {:.6g} J ({:.4g} Wh)\n", total, total / 3600);
  }
  return s;
}

/// The controlled nodes (members of band requirements) against time with their bands.
std::string design_plot(const std::vector<CheckedRun>& runs, const std::string& title) {
  plot::Figure fig;
  fig.title = title;
  for (const auto& r : runs) {
    plot::Panel panel;
    panel.title = "case " + r.net->spec().settings.name;
    panel.x_label = "time";
    panel.y_label = "T [°C]";
    panel.x_is_time_s = true;
    const double t_end = r.kept.times.empty() ? 0.0 : r.kept.times.back();
    for (const auto& o : r.outcomes) {
      if (o.req->kind != lang::RequirementKind::band) continue;
      plot::Band b;
      b.label = fmt::format("band {}", fmt::join(o.req->groups, ", "));
      b.x = {o.req->from, t_end};
      b.lo = {o.req->lo - lang::kZeroCelsius, o.req->lo - lang::kZeroCelsius};
      b.hi = {o.req->hi - lang::kZeroCelsius, o.req->hi - lang::kZeroCelsius};
      panel.bands.push_back(std::move(b));
    }
    for (std::size_t c = 0; c < r.kept.names.size(); ++c) {
      plot::Series s;
      s.label = r.kept.names[c];
      s.x = r.kept.times;
      for (const auto& row : r.kept.temps)
        s.y.push_back(row[c] - lang::kZeroCelsius);
      panel.series.push_back(std::move(s));
    }
    fig.panels.push_back(std::move(panel));
  }
  return plot::render_svg(fig);
}

/// The node names of the band requirements (what the plot shows).
std::vector<std::string> controlled_nodes(const lang::Model& model, const std::string& case_name) {
  std::set<std::string> seen;
  std::vector<std::string> out;
  const auto spec = model.network(case_name);
  for (const auto& r : spec->requirements)
    if (r.kind == lang::RequirementKind::band)
      for (int i : r.members)
        if (seen.insert(spec->nodes[static_cast<std::size_t>(i)].name).second)
          out.push_back(spec->nodes[static_cast<std::size_t>(i)].name);
  return out;
}

int run_design(const DesignOptions& o, lang::SourceManager& sources) {
  const char* me = "thermnet design";
  int status = exit_ok;
  auto model = load_checked_model(o.model, sources, status, o.sets);
  if (!model) return status;
  check_outputs({{"-o", o.out}, {"--json", o.json}, {"--plot", o.plot}}, model_inputs(*model));
  if (model->requirements().empty()) {
    std::cerr << fmt::format("{}: error: {} states no requirement to design for (add e.g. "
                             "`require band \"lens*\" 15 .. 25 [degC]`)\n",
                             me, o.model);
    return exit_failure;
  }
  std::vector<lang::ParamInfo> params = design_params(*model, o.params);
  if (params.empty()) {
    std::cerr << fmt::format("{}: error: no param in {} has a range; nothing to choose (declare "
                             "e.g. `param P_zone = 5 [W] range 1 .. 20`)\n",
                             me, o.model);
    return exit_failure;
  }
  refuse_repeated_cases(o.cases);
  std::vector<std::string> cases;
  for (const auto& c : o.cases.empty() ? model->run_case_names() : o.cases)
    cases.push_back(model->resolve_case(c));
  const DesignObjective objective =
      o.objective == "power" ? DesignObjective::power : DesignObjective::energy;
  DesignProblem problem(*model, params, cases, objective, SimulationOptions{});
  DesignSettings settings;
  settings.samples = o.samples > 0 ? o.samples : 4 * (params.size() + 1);
  settings.evaluations = o.evaluations;
  settings.seed = o.seed;
  settings.threads = o.threads;
  std::cerr << fmt::format(
      "{}: {} param{} over {} case{}, minimising {}; {} samples, then compass "
      "search (at most {} evaluations)\n",
      me, params.size(), params.size() == 1 ? "" : "s", cases.size(), cases.size() == 1 ? "" : "s",
      objective == DesignObjective::energy ? "heater energy" : "installed heater power",
      settings.samples, settings.evaluations);
  const DesignResult result = design_search(problem, settings);
  if (!result.best.ok) {
    std::cerr << fmt::format("{}: error: no design point could be simulated: {}\n", me,
                             result.best.failure);
    return exit_failure;
  }
  const std::vector<std::string> keep = controlled_nodes(*model, cases.front());
  const std::vector<CheckedRun> runs = problem.run(result.best.x, keep);
  const DesignPoint best = problem.score(result.best.x, runs);
  std::vector<RequirementOutcome> outcomes;
  for (const auto& r : runs)
    outcomes.insert(outcomes.end(), r.outcomes.begin(), r.outcomes.end());

  std::string text = fmt::format("{} at the {} point ({} evaluations, {} failed):\n",
                                 best.feasible ? "designed values" : "values",
                                 best.feasible ? "chosen" : "best (infeasible)", result.evaluations,
                                 result.failed);
  nlohmann::json jvalues = nlohmann::json::object();
  for (std::size_t j = 0; j < params.size(); ++j) {
    const auto& p = params[j];
    text += fmt::format("  {} = {}   (range {} .. {}; declared {})\n", p.name, show(p, best.x[j]),
                        show(p, *p.lo), show(p, *p.hi), show(p, p.value));
    jvalues[p.name] = best.x[j];
  }
  text += "requirements:\n" + outcomes_text(outcomes, sources);
  nlohmann::json jsources;
  text += sources_table(runs, jsources);
  text += objective == DesignObjective::energy
              ? fmt::format("objective: heater energy {:.6g} J over {} case{}\n", best.objective,
                            cases.size(), cases.size() == 1 ? "" : "s")
              : fmt::format("objective: installed heater power {:.6g} W\n", best.objective);
  std::cout << text;
  std::cout.flush();

  std::vector<OutputFile> files;
  if (!o.json.empty())
    files.push_back({o.json, nlohmann::json{{"model", model->name()},
                                            {"feasible", best.feasible},
                                            {"objective", o.objective},
                                            {"objective_value", best.objective},
                                            {"evaluations", result.evaluations},
                                            {"seed", o.seed},
                                            {"params", jvalues},
                                            {"requirements", outcomes_json(outcomes, sources)},
                                            {"sources", jsources}}
                                     .dump(1) +
                                 "\n"});
  if (!o.plot.empty())
    files.push_back({o.plot, design_plot(runs, fmt::format("{} — designed ({})", model->name(),
                                                           best.feasible ? "all requirements met"
                                                                         : "infeasible"))});
  if (best.feasible && !o.out.empty()) {
    note_sets_not_written(*model, me, o.out);
    std::vector<rewrite::ParamUpdate> updates;
    for (std::size_t j = 0; j < params.size(); ++j)
      updates.push_back({params[j], best.x[j]});
    const long root = model->sources().find(model->path());
    if (root < 0) throw OutputError("the model's own text is no longer available");
    for (const auto& f :
         rewrite::rewrite_model(model->sources(), static_cast<lang::FileId>(root), updates, o.out))
      files.push_back({f.path, f.text, f.chosen ? Follow::never : Follow::symlinks});
  }
  write_output_files(files);
  if (!best.feasible) {
    std::cerr << fmt::format("{}: error: the requirements cannot be met within the ranges; at the "
                             "best point found:\n",
                             me);
    for (const auto& oc : outcomes)
      if (!oc.met) std::cerr << "  " << format_outcome(oc, sources) << "\n";
    if (!o.out.empty()) std::cerr << fmt::format("{}: {} not written\n", me, o.out);
    return exit_failure;
  }
  return exit_ok;
}

} // namespace

void add_design_command(CLI::App& app, int& status) {
  auto o = std::make_shared<DesignOptions>();
  CLI::App* cmd = app.add_subcommand(
      "design", "Choose the ranged params (heater powers, set points) to meet the model's "
                "requirements at the least energy or installed power");
  cmd->add_option("MODEL", o->model, "model file (.tnet)")->required();
  cmd->add_option("--param", o->params,
                  "ranged params to choose (repeat or separate by commas; default: every ranged "
                  "param; the others keep their declared values)")
      ->delimiter(',');
  cmd->add_option("--case", o->cases, "cases the requirements must hold in (default: every case)")
      ->delimiter(',');
  add_set_option(cmd, o->sets,
                 "; held for the whole design (a designed param takes its chosen value)");
  cmd->add_option("--objective", o->objective,
                  "what to minimise: energy (heat supplied by all sources over the cases, "
                  "default) or power (installed power: the sum of the sources' P)")
      ->check(CLI::IsMember({"energy", "power"}));
  cmd->add_option("--samples", o->samples,
                  "seeded samples of the ranges before the local search (default 4 (p + 1))");
  cmd->add_option("--evaluations", o->evaluations,
                  "budget of the compass search, in evaluations (default 300)");
  cmd->add_option("--seed", o->seed, "random seed of the samples (same seed, same design)");
  cmd->add_option("--threads", o->threads, "workers of the sample stage (0: all cores)")
      ->check(rule_validator(non_negative_whole_rule, "INT"));
  cmd->add_option("-o,--out", o->out,
                  "write the model with the designed values in place (as calibrate -o); only "
                  "when every requirement is met")
      ->check(output_file_validator());
  cmd->add_option("--json", o->json,
                  "write {model, feasible, objective, objective_value, evaluations, seed, params, "
                  "requirements: [...], sources: [...]}")
      ->check(output_file_validator());
  cmd->add_option("--plot", o->plot,
                  "SVG plot of the nodes of the band requirements, with their bands")
      ->check(output_file_validator());
  cmd->callback([o, &status] {
    status = run_command("thermnet design",
                         [&](lang::SourceManager& sources) { return run_design(*o, sources); });
  });
}

} // namespace thermnet::cli
