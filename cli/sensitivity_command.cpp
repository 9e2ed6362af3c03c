#include "cli/sensitivity_command.hpp"

#include "app/sensitivity_report.hpp"

#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "app/option_rules.hpp"
#include "app/output_files.hpp"
#include "app/param_overrides.hpp"
#include "cli/run_command.hpp"
#include "kernel/calibration/sensitivity.hpp"
#include "kernel/core/simulation.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

namespace thermnet::cli {
using namespace app;
namespace {

struct SensitivityCommandOptions {
  std::string model;
  std::string json;
  bool elements = false;
  std::vector<std::string> cases;
  int threads = 0;
  std::vector<std::string> sets;
};

std::string format_value(const SensitivityFactor& f) {
  if (f.lo && f.hi) return fmt::format("{:.4g} .. {:.4g}", *f.lo, *f.hi);
  if (std::isnan(f.value)) return "signal";
  if (f.temperature) return fmt::format("{:.4g} degC", f.value - lang::kZeroCelsius);
  return fmt::format("{:.4g}", f.value);
}

/// The table: one row per factor by rank, one column per output node, then the total.
std::string format_table(const SensitivityReport& r) {
  std::size_t name_w = 6, value_w = 11;
  for (const auto& f : r.factors) {
    name_w = std::max(name_w, f.name.size());
    value_w = std::max(value_w, format_value(f).size());
  }
  std::string out = fmt::format(
      "normalised sensitivity, K: RMS over time of dT/dp x (hi - lo) for ranged params, "
      "x 1 K for set points (degC), x |p| otherwise; cases: {}\n",
      fmt::join(r.cases, ", "));
  out += fmt::format("{:>4}  {:<{}}  {:<{}}", "rank", "factor", name_w, "range/value", value_w);
  std::vector<std::size_t> widths;
  for (const auto& o : r.outputs) {
    widths.push_back(std::max<std::size_t>(9, o.size()));
    out += fmt::format("  {:>{}}", o, widths.back());
  }
  out += fmt::format("  {:>9}\n", "total");
  for (std::size_t k = 0; k < r.ranking.size(); ++k) {
    const std::size_t j = r.ranking[k];
    const SensitivityFactor& f = r.factors[j];
    out += fmt::format("{:>4}  {:<{}}  {:<{}}", k + 1, f.name, name_w, format_value(f), value_w);
    for (std::size_t i = 0; i < r.outputs.size(); ++i)
      out += fmt::format("  {:>{}.4g}", r.matrix[j][i], widths[i]);
    out += fmt::format("  {:>9.4g}\n", r.total[j]);
  }
  return out;
}

int run_sensitivity(const SensitivityCommandOptions& o, lang::SourceManager& sources) {
  int status = exit_ok;
  auto model = load_checked_model(o.model, sources, status, o.sets);
  if (!model) return status;
  check_outputs({{"--json", o.json}}, model_inputs(*model));
  SensitivityOptions opt;
  opt.elements = o.elements;
  refuse_repeated_cases(o.cases);
  opt.cases = o.cases;
  opt.threads = o.threads;
  SensitivityReport r = compute_sensitivities(*model, opt);
  std::cout << format_table(r);
  for (const auto& n : r.notes)
    std::cerr << "thermnet sensitivity: note: " << n << "\n";
  std::cerr << fmt::format("thermnet sensitivity: {} simulations\n", r.simulations);
  if (!o.json.empty()) write_output_file(o.json, sensitivity_json(*model, r).dump(2) + "\n");
  return exit_ok;
}

} // namespace

void add_sensitivity_command(CLI::App& app, int& status) {
  auto o = std::make_shared<SensitivityCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sensitivity", "Rank params (and element values) by their effect on node temperatures");
  cmd->add_option("MODEL", o->model, "model file (.tnet)")->required();
  cmd->add_option("--json", o->json, "write the matrix and the ranking as JSON")
      ->check(output_file_validator());
  cmd->add_flag("--elements", o->elements,
                "also every numeric element key and node capacity (relative 1 % steps)");
  cmd->add_option("--case", o->cases, "case(s) to use (default: every case with data)");
  cmd->add_option("--threads", o->threads, "worker threads (0: all cores)")
      ->check(rule_validator(non_negative_whole_rule, "INT"));
  add_set_option(cmd, o->sets, "; the derivatives are taken at these values");
  cmd->callback([o, &status] {
    status = run_command("thermnet sensitivity", [&](lang::SourceManager& sources) {
      return run_sensitivity(*o, sources);
    });
  });
}

} // namespace thermnet::cli
