#include "cli/lint_command.hpp"

#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "cli/run_command.hpp"

#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <unistd.h>

namespace thermnet::cli {
using namespace app;
namespace {

struct LintOptions {
  std::vector<std::string> models;
  std::string format = "text";
  bool werror = false;
};

int run_lint(const LintOptions& o, lang::SourceManager& sources) {
  lang::DiagnosticEngine diags(sources);
  bool unreadable = false;
  for (const auto& path : o.models) {
    if (diags.saturated()) break;
    auto model = load_model(path, sources, diags, ModelPlugins::never, "thermnet lint");
    if (!model) {
      unreadable = true;
      continue;
    }
    model->lint(diags);
  }
  diags.sort();
  if (o.format == "json")
    std::cout << lang::render_json(diags);
  else if (o.format == "sarif")
    std::cout << lang::render_sarif(diags, THERMNET_VERSION);
  else {
    std::cout << lang::render_text(diags, use_color(STDOUT_FILENO));
    std::size_t e = diags.error_count(), w = diags.warning_count(), n = o.models.size();
    if (e || w)
      std::cerr << fmt::format("{} error{} and {} warning{} in {} model{}.\n", e, e == 1 ? "" : "s",
                               w, w == 1 ? "" : "s", n, n == 1 ? "" : "s");
  }
  std::cout.flush();
  if (unreadable || reports_unreadable_file(diags)) return exit_usage;
  if (diags.error_count() > 0 || (o.werror && diags.warning_count() > 0)) return exit_failure;
  return exit_ok;
}

} // namespace

void add_lint_command(CLI::App& app, int& status) {
  auto opts = std::make_shared<LintOptions>();
  CLI::App* cmd = app.add_subcommand("lint", "Check model files and report every problem found");
  cmd->add_option("MODEL", opts->models, "model files (.tnet)")->required();
  cmd->add_option("--format", opts->format, "output format")
      ->check(CLI::IsMember({"text", "json", "sarif"}))
      ->default_str("text");
  cmd->add_flag("--werror", opts->werror, "treat warnings as errors (exit status 1)");
  cmd->callback([opts, &status] {
    status = run_command("thermnet lint",
                         [&](lang::SourceManager& sources) { return run_lint(*opts, sources); });
  });
}

} // namespace thermnet::cli
