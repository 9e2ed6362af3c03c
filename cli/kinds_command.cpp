#include "cli/kinds_command.hpp"

#include "app/exit_status.hpp"
#include "app/schema_text.hpp"
#include "cli/run_command.hpp"
#include "kernel/calibration/optimizer.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/diagnosis/hypothesis.hpp"
#include "kernel/estimation/estimator.hpp"
#include "lang/diagnostics.hpp"

#include <fmt/format.h>

#include <iostream>
#include <map>
#include <memory>
#include <optional>

namespace thermnet::cli {
using namespace app;
namespace {

struct KindsOptions {
  std::vector<std::string> kinds;
  std::string family; // empty: every family
  std::string format = "text";
};

/// A markdown table cell: '|' would end the cell.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text)
    out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string describe(const ElementPlugin& p, bool markdown) {
  const lang::ElementSchema& s = p.schema;
  std::string out;
  if (markdown) {
    out += fmt::format("## `{}`\n\n{} ({} terminal{}).\n\n", s.kind, s.doc, s.terminals,
                       s.terminals == 1 ? "" : "s");
    out += app::key_table_markdown(s);
  } else {
    out += fmt::format("{} ({} terminal{}): {}\n", s.kind, s.terminals, s.terminals == 1 ? "" : "s",
                       s.doc);
    for (const auto& k : s.keys)
      out += fmt::format("  {:<8} [{}] {}{}: {}\n", k.name, app::key_unit(k), app::key_default(k),
                         k.range_text().empty() ? "" : ", " + k.range_text(), k.doc);
  }
  if (const std::string groups = app::alternatives_text(s); !groups.empty())
    out += markdown ? fmt::format("\nGive exactly one of: {}.\n", groups)
                    : fmt::format("  give exactly one of: {}\n", groups);
  out += "\n";
  return out;
}

std::string describe(const OptimizerPlugin& p, bool markdown) {
  if (markdown) return fmt::format("| `{}` | {} | {} |\n", p.name, cell(p.doc), cell(p.budget));
  return fmt::format("{}: {}\n  budget (--samples): {}\n\n", p.name, p.doc, p.budget);
}

std::string describe(const EstimatorPlugin& p, bool markdown) {
  std::string options;
  for (const auto& o : p.options)
    options += fmt::format("{}{}--{}{}{}", options.empty() ? "" : ", ", markdown ? "`" : "", o.name,
                           markdown ? "`" : "",
                           o.default_value.empty() ? "" : " (" + o.default_value + ")");
  if (markdown)
    return fmt::format("| `{}` | {} | {} | {} |\n", p.name, cell(p.doc),
                       p.needs_model ? "yes" : "no", cell(options));
  std::string out =
      fmt::format("{}{}: {}\n", p.name, p.needs_model ? " (needs a model)" : "", p.doc);
  for (const auto& o : p.options)
    out +=
        fmt::format("  --{:<14} {}{}\n", o.name, o.doc,
                    o.default_value.empty() ? "" : fmt::format(" (default {})", o.default_value));
  return out + "\n";
}

std::string describe(const HypothesisPlugin& p, bool markdown) {
  if (markdown)
    return fmt::format("| `{}` | {} | {} | {} | {} |\n", p.name, cell(p.doc), cell(p.screen),
                       cell(p.fitted), cell(p.writes));
  return fmt::format("{}: {}\n  screen term: {}\n  fitted: {}\n  --write adds: {}\n\n", p.name,
                     p.doc, p.screen, p.fitted, p.writes);
}

/// How each family is titled and tabulated.
template <class Plugin> struct FamilyText;
template <> struct FamilyText<ElementPlugin> {
  static constexpr const char* title = "Element kinds";
  static constexpr const char* use = "model statements";
  static constexpr const char* table_head = "";
};
template <> struct FamilyText<OptimizerPlugin> {
  static constexpr const char* title = "Optimizers";
  static constexpr const char* use = "calibrate --method";
  static constexpr const char* table_head = "| method | what it does | budget (`--samples`) |\n"
                                            "|---|---|---|\n";
};
template <> struct FamilyText<EstimatorPlugin> {
  static constexpr const char* title = "Estimators";
  static constexpr const char* use = "estimate --method, invert";
  static constexpr const char* table_head = "| method | what it does | needs a model | options "
                                            "(default) |\n|---|---|---|---|\n";
};
template <> struct FamilyText<HypothesisPlugin> {
  static constexpr const char* title = "Diagnosis hypotheses";
  static constexpr const char* use = "finding kinds of diagnose";
  static constexpr const char* table_head = "| kind | meaning | screen term | fitted | what "
                                            "`--write` adds |\n|---|---|---|---|---|\n";
};

/// Prints the named kinds of one family (all of them when `names` is empty) under its heading.
template <class Plugin>
void print_family(const std::vector<std::string>& names, bool markdown, bool heading) {
  using Text = FamilyText<Plugin>;
  const auto& registry = Registry<Plugin>::global();
  if (heading)
    std::cout << (markdown
                      ? fmt::format("# {}\n\nGenerated by `thermnet kinds --family {} --format "
                                    "markdown`.\n\n",
                                    Text::title, PluginTraits<Plugin>::family)
                      : fmt::format("{} ({}):\n\n", Text::title, Text::use));
  if (markdown) std::cout << Text::table_head;
  for (const auto& name : names.empty() ? registry.names() : names)
    std::cout << describe(*registry.find(name), markdown);
  if (markdown && *Text::table_head) std::cout << "\n";
}

/// The family that has a kind of this name, or nullopt (elements first).
std::optional<std::string> family_of(const std::string& name) {
  if (ElementRegistry::global().find(name)) return "element";
  if (OptimizerRegistry::global().find(name)) return "optimizer";
  if (EstimatorRegistry::global().find(name)) return "estimator";
  if (HypothesisRegistry::global().find(name)) return "hypothesis";
  return std::nullopt;
}

/// Every kind name of the family (or of all families when empty).
std::vector<std::string> all_names(const std::string& family) {
  std::vector<std::string> out;
  auto add = [&](const char* f, std::vector<std::string> names) {
    if (family.empty() || family == f) out.insert(out.end(), names.begin(), names.end());
  };
  add("element", ElementRegistry::global().names());
  add("optimizer", OptimizerRegistry::global().names());
  add("estimator", EstimatorRegistry::global().names());
  add("hypothesis", HypothesisRegistry::global().names());
  return out;
}

int run_kinds(const KindsOptions& o) {
  const bool markdown = o.format == "markdown";
  // Named kinds, grouped by family in the families' order.
  std::map<std::string, std::vector<std::string>> named;
  for (const auto& k : o.kinds) {
    std::optional<std::string> f = family_of(k);
    if (f && !o.family.empty() && *f != o.family) f.reset();
    if (!f) {
      std::cerr << fmt::format("thermnet kinds: error: unknown {}kind '{}'",
                               o.family.empty() ? std::string() : o.family + " ", k);
      if (auto m = lang::closest_match(k, all_names(o.family)))
        std::cerr << fmt::format("; did you mean '{}'?", *m);
      std::cerr << "\n";
      return exit_failure;
    }
    named[*f].push_back(k);
  }
  const bool heading = o.kinds.empty();
  auto family = [&](const char* f, auto print) {
    if (!o.family.empty() && o.family != f) return;
    if (!o.kinds.empty() && !named.count(f)) return;
    print(named[f], markdown, heading);
  };
  family("element", print_family<ElementPlugin>);
  family("optimizer", print_family<OptimizerPlugin>);
  family("estimator", print_family<EstimatorPlugin>);
  family("hypothesis", print_family<HypothesisPlugin>);
  return exit_ok;
}

} // namespace

void add_kinds_command(CLI::App& app, int& status) {
  auto o = std::make_shared<KindsOptions>();
  CLI::App* cmd = app.add_subcommand(
      "kinds", "List the plugin kinds: element kinds (keys, units, defaults), optimizers, "
               "estimators and diagnosis hypotheses");
  cmd->add_option("KIND", o->kinds, "kinds to describe (default: all of the families shown)");
  cmd->add_option("--family", o->family, "only this family")
      ->check(CLI::IsMember({"element", "optimizer", "estimator", "hypothesis"}));
  cmd->add_option("--format", o->format, "output format")
      ->check(CLI::IsMember({"text", "markdown"}));
  cmd->callback([o, &status] {
    status = run_command("thermnet kinds", [&](lang::SourceManager&) { return run_kinds(*o); });
  });
}

} // namespace thermnet::cli
