#pragma once
/// Loading models for the subcommands: one place that wires the registry, checking and reporting.

#include "app/output_files.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"

#include <memory>
#include <optional>
#include <string>

namespace CLI {
class App;
} // namespace CLI

namespace thermnet::app {

/// Loads a plugin library (path absolute or relative to the working directory) into the global
/// registries; returns what went wrong, or nothing (also when it was loaded before).
std::optional<std::string> load_plugin(const std::string& path);

/// What a model's `plugin "lib.so"` statement may do: a model is untrusted input, so its
/// statements load code only when the user asked (--allow-model-plugins or
/// THERMNET_ALLOW_MODEL_PLUGINS=1); lint and the language server never load it.
enum class ModelPlugins {
  if_allowed, ///< load when the user allowed model plugins; otherwise an error naming the flag
  never       ///< never load (lint, lsp); an error unless the library came by --plugin
};

/// The options a command loads models with: `plugin "lib.so"` statements are accepted without
/// loading anything when the same library came by --plugin, else handled as `plugins` says.
/// `who` names the command in the refusal ("thermnet lint").
lang::LoadOptions load_options(ModelPlugins plugins, const std::string& who);

/// Adds the global, repeatable `--plugin PATH` option (also accepted after the subcommand): each
/// library is loaded while the command line is parsed, before any subcommand runs; a library that
/// cannot be loaded ends the run with "thermnet: error: cannot load plugin ...". Adds the other
/// global trust options too: `--allow-model-plugins` and `--allow-outside-paths`.
void add_plugin_option(CLI::App& app);

/// Loads a model against the global element registry; problems go to diags. A model's plugin
/// statements load only if allowed (ModelPlugins::if_allowed) or never; the files it names are
/// read under the path policy of its folder (lang/path_policy.hpp), set here for the run.
std::unique_ptr<lang::Model> load_model(const std::string& path, lang::SourceManager& sources,
                                        lang::DiagnosticEngine& diags,
                                        ModelPlugins plugins = ModelPlugins::if_allowed,
                                        const std::string& who = "thermnet");

/// Every file a loaded model reads (its files, then its data, table and plugin files), as the
/// inputs its run's outputs must not overwrite.
std::vector<NamedInput> model_inputs(const lang::Model& model);

/// True when a diagnostic says a file (model, include, data or table) could not be read.
bool reports_unreadable_file(const lang::DiagnosticEngine& diags);

/// Loads and lints a model for a command; on errors prints them to stderr, sets `status` and
/// returns nullptr (status 2 when a file it needs cannot be read, 1 for errors in it). Then sets
/// the values of the command's `--set` items (app/param_overrides.hpp), which every later use of
/// the model sees; throws lang::OverrideError when they are wrong.
std::unique_ptr<lang::Model> load_checked_model(const std::string& path,
                                                lang::SourceManager& sources, int& status,
                                                const std::vector<std::string>& sets = {});

/// Prints a model error found while running a command and returns the exit status it calls for:
/// 2 for a wrong or missing --case or a file that cannot be read, 1 otherwise.
int report_model_error(const lang::ModelError& e, const lang::SourceManager& sources);

/// Prints one diagnostic (e.g. from a ModelError) to stderr, compiler-style.
void print_diagnostic(const lang::Diagnostic& d, const lang::SourceManager& sources);

/// Throws lang::OverrideError when `cases` (given with --case) names a case twice: it would run,
/// and count, twice.
void refuse_repeated_cases(const std::vector<std::string>& cases);

/// Parses a time such as "2500", "3h", "45 min" or "1.5 [h]" into seconds; throws
/// std::invalid_argument.
double parse_time(const std::string& text);

/// True when stderr/stdout should be coloured (a terminal, and NO_COLOR unset).
bool use_color(int fd);

} // namespace thermnet::app
