#include "app/model_loading.hpp"

#include "app/exit_status.hpp"
#include "app/huge_page_heap.hpp"
#include "app/param_overrides.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/plugin_host/plugin_loader.hpp"
#include "lang/path_policy.hpp"
#include "lang/rewrite/model_files.hpp"
#include "lang/units.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <set>
#include <stdexcept>
#include <string_view>
#include <unistd.h>

namespace thermnet::app {

std::optional<std::string> load_plugin(const std::string& path) {
  std::error_code ec;
  std::filesystem::path absolute = std::filesystem::absolute(path, ec);
  return PluginLoader::global().load(ec ? path : absolute.string());
}

namespace {

/// Set by --allow-model-plugins.
bool allow_model_plugins_flag = false;

/// Whether the user allowed a model's plugin statements to load code.
bool model_plugins_allowed() {
  if (allow_model_plugins_flag) return true;
  const char* env = std::getenv("THERMNET_ALLOW_MODEL_PLUGINS");
  return env != nullptr && std::string_view(env) == "1";
}

/// Whether the library at `path` was loaded already (by --plugin): accepting its statement then
/// runs no new code. Compares canonical paths, without opening the file.
bool already_loaded(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
  if (ec) return false;
  const std::vector<std::string> loaded = PluginLoader::global().loaded();
  return std::find(loaded.begin(), loaded.end(), canonical.string()) != loaded.end();
}

} // namespace

lang::LoadOptions load_options(ModelPlugins plugins, const std::string& who) {
  lang::LoadOptions options;
  options.load_plugin = [plugins, who](const std::string& path) -> std::optional<std::string> {
    if (already_loaded(path)) return std::nullopt;
    if (plugins == ModelPlugins::never)
      return fmt::format("{} never runs code named by a model; to check a model that uses this "
                         "plugin, load it yourself with --plugin PATH",
                         who);
    if (!model_plugins_allowed())
      return "a model's plugin statement loads code only when you allow it: pass "
             "--allow-model-plugins (or set THERMNET_ALLOW_MODEL_PLUGINS=1) if you trust this "
             "model, or load the library with --plugin PATH";
    return load_plugin(path);
  };
  return options;
}

void add_plugin_option(CLI::App& app) {
  app.add_option_function<std::vector<std::string>>(
         "--plugin",
         [](const std::vector<std::string>& paths) {
           for (const auto& path : paths)
             if (auto err = load_plugin(path))
               throw std::runtime_error(fmt::format("cannot load plugin '{}': {}", path, *err));
         },
         "load element/optimizer/estimator kinds from a plugin library (repeatable)")
      ->type_name("PATH")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app.add_flag("--allow-model-plugins", allow_model_plugins_flag,
               "let the model's `plugin` statements load their libraries (runs the model's code; "
               "never in lint or lsp; also THERMNET_ALLOW_MODEL_PLUGINS=1)");
  app.add_flag_callback(
      "--allow-outside-paths", [] { lang::set_allow_outside_paths(true); },
      "let a model read include, data and table files outside its own folder tree (never FIFOs, "
      "devices, /proc or /sys; also THERMNET_ALLOW_OUTSIDE_PATHS=1)");
  // Subcommands hand options they do not know to the top level, so `thermnet simulate --plugin
  // lib.so model.tnet` works too; subcommands added later inherit this.
  app.fallthrough();
  for (CLI::App* sub : app.get_subcommands({}))
    sub->fallthrough();
}

std::unique_ptr<lang::Model> load_model(const std::string& path, lang::SourceManager& sources,
                                        lang::DiagnosticEngine& diags, ModelPlugins plugins,
                                        const std::string& who) {
  lang::set_path_policy(lang::policy_for_model(path));
  std::error_code ec;
  if (const auto size = std::filesystem::file_size(path, ec); !ec) prefault_heap_for(size);
  return lang::Model::load(path, element_catalog(), sources, diags, load_options(plugins, who));
}

std::vector<NamedInput> model_inputs(const lang::Model& model) {
  const long root = model.sources().find(model.path());
  if (root < 0) return {{model.path(), "the model"}};
  // The model's syntax trees are whole unless loading stopped at the error limit (which takes
  // syntax or load errors): then the files are parsed again.
  std::vector<const lang::ast::File*> parsed;
  if (model.syntax_errors() == 0 && !model.load_error())
    for (const auto& file : model.files())
      parsed.push_back(file.get());
  std::vector<NamedInput> inputs;
  for (auto& f : rewrite::files_read(model.sources(), static_cast<lang::FileId>(root), parsed))
    inputs.push_back({std::move(f.path), std::move(f.role)});
  return inputs;
}

namespace {

/// True for the codes of a file that could not be read (the model, an include, data, a table).
bool is_unreadable_code(const std::string& code) {
  return code == "file-unreadable" || code == "include-unreadable" || code == "data-unreadable";
}

} // namespace

bool reports_unreadable_file(const lang::DiagnosticEngine& diags) {
  return std::any_of(diags.all().begin(), diags.all().end(), [](const lang::Diagnostic& d) {
    return d.severity == lang::Severity::error && is_unreadable_code(d.code);
  });
}

std::unique_ptr<lang::Model> load_checked_model(const std::string& path,
                                                lang::SourceManager& sources, int& status,
                                                const std::vector<std::string>& sets) {
  lang::DiagnosticEngine diags(sources);
  auto model = load_model(path, sources, diags);
  if (model) model->lint(diags);
  diags.sort();
  if (!diags.all().empty()) std::cerr << lang::render_text(diags, use_color(STDERR_FILENO));
  if (!model) {
    status = exit_usage;
    return nullptr;
  }
  if (diags.error_count() > 0) {
    std::cerr << fmt::format("thermnet: {} error{} in the model; nothing was run\n",
                             diags.error_count(), diags.error_count() == 1 ? "" : "s");
    status = reports_unreadable_file(diags) ? exit_usage : exit_failure;
    return nullptr;
  }
  if (!sets.empty()) model->set_overrides(parse_sets(*model, sets));
  return model;
}

int report_model_error(const lang::ModelError& e, const lang::SourceManager& sources) {
  print_diagnostic(e.diag, sources);
  const std::string& c = e.diag.code;
  const bool usage = c == "choose-case" || c == "unknown-case" || is_unreadable_code(c);
  return usage ? exit_usage : exit_failure;
}

void print_diagnostic(const lang::Diagnostic& d, const lang::SourceManager& sources) {
  lang::DiagnosticEngine one(sources);
  one.add(d);
  std::cerr << lang::render_text(one, use_color(STDERR_FILENO));
}

void refuse_repeated_cases(const std::vector<std::string>& cases) {
  std::set<std::string_view> seen;
  for (const auto& c : cases)
    if (!seen.insert(c).second)
      throw lang::OverrideError(
          fmt::format("--case: case '{}' is given twice (each case is run once)", c));
}

double parse_time(const std::string& text) {
  std::size_t b = text.find_first_not_of(" \t");
  if (b == std::string::npos) throw std::invalid_argument("empty time");
  double value = 0;
  auto [p, ec] = std::from_chars(text.data() + b, text.data() + text.size(), value);
  if (ec != std::errc())
    throw std::invalid_argument(fmt::format("'{}' is not a time (e.g. 2500, 3h, 45min)", text));
  std::string unit(p, text.data() + text.size());
  unit.erase(0, unit.find_first_not_of(" \t["));
  while (!unit.empty() && (unit.back() == ' ' || unit.back() == ']'))
    unit.pop_back();
  double seconds = value;
  if (!unit.empty()) {
    lang::Unit u;
    try {
      u = lang::parse_unit(unit);
    } catch (const lang::UnitError& e) {
      throw std::invalid_argument(fmt::format("'{}': {}", text, e.what()));
    }
    if (!(u.dim == lang::dim::time))
      throw std::invalid_argument(
          fmt::format("'{}' is not a time: its unit is {}", text, lang::describe(u.dim)));
    seconds = u.scale * value;
  }
  if (!std::isfinite(seconds) || seconds <= 0)
    throw std::invalid_argument(fmt::format("'{}' must be a positive time", text));
  return seconds;
}

bool use_color(int fd) {
  return ::isatty(fd) && std::getenv("NO_COLOR") == nullptr;
}

} // namespace thermnet::app
