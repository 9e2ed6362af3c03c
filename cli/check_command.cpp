// `thermnet check MODEL`: runs every case a requirement applies to (or those given by --case) and
// reports each requirement: met with its margin, or violated with where, when and by how much.

#include "cli/check_command.hpp"

#include "app/checked_run.hpp"
#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "app/option_rules.hpp"
#include "app/output_files.hpp"
#include "app/param_overrides.hpp"
#include "app/requirement_report.hpp"
#include "cli/run_command.hpp"

#include <fmt/format.h>

#include <iostream>

namespace thermnet::cli {
using namespace app;
namespace {

struct CheckOptions {
  std::string model;
  std::vector<std::string> cases;
  std::vector<std::string> sets;
  std::string json;
};

int run_check(const CheckOptions& o, lang::SourceManager& sources) {
  int status = exit_ok;
  auto model = load_checked_model(o.model, sources, status, o.sets);
  if (!model) return status;
  check_outputs({{"--json", o.json}}, model_inputs(*model));
  if (model->requirements().empty()) {
    std::cerr << fmt::format("thermnet check: error: {} states no requirement (add e.g. `require "
                             "band \"lens*\" 15 .. 25 [degC]`)\n",
                             o.model);
    return exit_failure;
  }
  refuse_repeated_cases(o.cases);
  std::vector<std::string> cases = o.cases;
  if (cases.empty()) cases = model->run_case_names();
  std::vector<CheckedRun> runs;
  std::vector<RequirementOutcome> all;
  for (const auto& c : cases) {
    runs.push_back(run_checked(*model, model->resolve_case(c), {}, SimulationOptions{}));
    all.insert(all.end(), runs.back().outcomes.begin(), runs.back().outcomes.end());
  }
  std::cout << outcomes_text(all, sources);
  const std::size_t bad = violations(all);
  std::cout << fmt::format("{} of {} requirement checks over {} case{} violated\n", bad, all.size(),
                           cases.size(), cases.size() == 1 ? "" : "s");
  std::cout.flush();
  if (!o.json.empty())
    write_output_files({{o.json, nlohmann::json{{"model", model->name()},
                                                {"met", bad == 0},
                                                {"violations", bad},
                                                {"requirements", outcomes_json(all, sources)}}
                                         .dump(1) +
                                     "\n"}});
  return bad == 0 ? exit_ok : exit_failure;
}

} // namespace

void add_check_command(CLI::App& app, int& status) {
  auto o = std::make_shared<CheckOptions>();
  CLI::App* cmd = app.add_subcommand(
      "check", "Run the cases and check the model's requirements (`require ...`); exit 1 when one "
               "is violated");
  cmd->add_option("MODEL", o->model, "model file (.tnet)")->required();
  cmd->add_option("--case", o->cases,
                  "cases to run (repeat or separate by commas; default: every case)")
      ->delimiter(',');
  add_set_option(cmd, o->sets);
  cmd->add_option("--json", o->json,
                  "write {model, met, violations, requirements: [{file, line, column, kind, "
                  "requirement, case, met, unit, worst, slack, time, where[, duty]}]}")
      ->check(output_file_validator());
  cmd->callback([o, &status] {
    status = run_command("thermnet check",
                         [&](lang::SourceManager& sources) { return run_check(*o, sources); });
  });
}

} // namespace thermnet::cli
