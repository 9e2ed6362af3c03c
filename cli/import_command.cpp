#include "cli/import_command.hpp"

#include "app/exit_status.hpp"
#include "app/model_loading.hpp"
#include "app/option_rules.hpp"
#include "app/output_files.hpp"
#include "app/output_stream.hpp"
#include "cli/run_command.hpp"
#include "import/importer.hpp"
#include "kernel/core/element_registry.hpp"
#include "lang/display_text.hpp"
#include "lang/path_policy.hpp"

#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <unistd.h>

namespace thermnet::cli {
using namespace app;
namespace {

struct ImportCommandOptions {
  std::vector<std::string> files;
  std::string output;
  std::string format;
  bool allow_partial = false;
};

std::string plural(std::size_t n, const std::string& word) {
  if (n == 1) return fmt::format("1 {}", word);
  if (word.back() == 'y') return fmt::format("{} {}ies", n, word.substr(0, word.size() - 1));
  return fmt::format("{} {}s", n, word);
}

int run_import(const ImportCommandOptions& o, lang::SourceManager& sources) {
  // The files named here are the user's choice; the files they include stay in the first one's
  // folder tree unless the user allows more (--allow-outside-paths), as a model's includes do.
  lang::set_path_policy(lang::policy_for_model(o.files.front()));
  std::vector<NamedInput> inputs;
  for (const auto& f : o.files) {
    lang::allow_named_path(f);
    inputs.push_back({f, "an imported file"});
  }
  if (!o.output.empty()) check_outputs({{"-o", o.output}}, inputs);

  importer::ImportOptions options;
  if (o.format == "sinda") options.format = importer::Format::sinda;
  if (o.format == "spice") options.format = importer::Format::spice;
  options.allow_partial = o.allow_partial;
  // (plugins given with --plugin are loaded by now: their kinds count too)
  options.is_kind = [](const std::string& n) {
    return thermnet::element_catalog().find(n) != nullptr;
  };
  lang::DiagnosticEngine diags(sources);
  const importer::ImportResult r = importer::import_files(o.files, options, diags, sources);
  if (diags.saturated()) diags.stop_early();
  if (!diags.all().empty()) std::cerr << lang::render_text(diags, use_color(STDERR_FILENO));
  if (r.failed) {
    if (diags.error_count() > 0)
      std::cerr << fmt::format("thermnet import: {}; nothing written\n",
                               plural(diags.error_count(), "error"));
    else
      std::cerr << fmt::format("thermnet import: {} not translated; nothing written (pass "
                               "--allow-partial to write the model without them)\n",
                               plural(r.dropped, "part"));
    return r.unreadable ? exit_usage : exit_failure;
  }
  if (o.output.empty()) {
    std::cout << r.text;
    std::cout.flush();
  } else {
    std::vector<NamedInput> all;
    for (const auto& f : r.files_read)
      all.push_back({f, "an imported file"});
    check_outputs({{"-o", o.output}}, all);
    write_output_file(o.output, r.text);
  }
  std::cerr << fmt::format(
      "thermnet import: {} ({}): {}, {}, {}, {}{}{}\n", lang::escape_for_display(o.files.front()),
      importer::format_name(r.format), plural(r.nodes, "node"), plural(r.boundaries, "boundary"),
      plural(r.links, "link"), plural(r.heaters, "heater"),
      r.dropped ? fmt::format("; {} not translated", plural(r.dropped, "part")) : "",
      o.output.empty() ? "" : " -> " + lang::escape_for_display(o.output));
  return exit_ok;
}

} // namespace

void add_import_command(CLI::App& app, int& status) {
  auto opts = std::make_shared<ImportCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "import",
      "Write a thermnet model from SINDA/FLUINT decks or a SPICE netlist (docs/import.md)");
  cmd->add_option("FILE", opts->files,
                  "the files to import, merged into one model (a SINDA deck and its radiation "
                  "conductor files, or a SPICE netlist)")
      ->required();
  cmd->add_option("-o,--output", opts->output, "write the model here (default: standard output)")
      ->check(output_file_validator());
  cmd->add_option("--format", opts->format, "the files' format (default: found from the content)")
      ->check(CLI::IsMember({"sinda", "spice"}));
  cmd->add_flag("--allow-partial", opts->allow_partial,
                "write the model even when parts of the files are not translated (they are "
                "still listed)");
  cmd->callback([opts, &status] {
    status = run_command("thermnet import",
                         [&](lang::SourceManager& sources) { return run_import(*opts, sources); });
  });
}

} // namespace thermnet::cli
