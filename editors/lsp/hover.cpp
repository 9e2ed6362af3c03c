#include "editors/lsp/hover.hpp"

#include "app/schema_text.hpp"
#include "editors/lsp/file_hover.hpp"
#include "editors/lsp/navigation.hpp"
#include "editors/lsp/position.hpp"
#include "editors/lsp/text_context.hpp"
#include "kernel/core/element_registry.hpp"

#include <fmt/format.h>

#include <optional>
#include <string>
#include <vector>

namespace thermnet::lsp {
using namespace app;
namespace {

/// The markdown of a key named by `cw`, owned by the statement or object around it.
std::optional<std::string> key_hover(const Document& doc, const CodeWord& cw) {
  const auto& registry = element_catalog();
  const std::string& text = doc.text();
  const Word& w = cw.word;
  const StatementContext& ctx = cw.where;
  std::string owner_kind;
  if (w.begin > 0 && text[w.begin - 1] == '.') { // `film.P`, `plate1.T0` in a case
    if (const lang::NodeDecl* n = find_node(doc.model(), ctx.object))
      owner_kind = n->boundary ? "boundary" : "node";
    else
      owner_kind = element_kind(doc.model(), ctx.object);
  } else if (!ctx.tokens.empty()) {
    owner_kind = ctx.tokens.front();
  } else if (ctx.block == "case") {
    owner_kind = "case";
  }
  if (const lang::ElementSchema* s = registry.find(owner_kind))
    if (const lang::KeySchema* k = s->key(w.text)) return key_markdown(*s, *k);
  for (const auto& [name, keydoc] : builtin_keys(owner_kind))
    if (name == w.text) return fmt::format("**{}** — key of `{}`\n\n{}", name, owner_kind, keydoc);
  return std::nullopt;
}

/// The markdown of the words that start loops and submodels, and of `time`.
std::optional<std::string> keyword_hover(const Word& w, const StatementContext& ctx) {
  if (w.text == "for" || (w.text == "in" && !ctx.tokens.empty() && ctx.tokens.front() == "for"))
    return std::string("**for** VAR **in** LO .. HI [, VAR **in** LO .. HI] { ... } — repeats its "
                       "statements for every whole number from LO to HI, both included");
  if (w.text == "submodel" && ctx.tokens.empty())
    return std::string("**submodel** NAME(TERMINAL, ...) { ... } — a reusable part; an instance "
                       "`NAME INSTANCE NODE ... key = value` prefixes its names with `INSTANCE.`");
  if (w.text == "require" && ctx.tokens.empty())
    return std::string("**require** band|gradient|power|energy|margin \"GROUP\"... LO .. HI | "
                       "max VALUE | min VALUE [from TIME] [in CASE, ...] — a requirement every run "
                       "must meet: checked by `thermnet check`, met by `thermnet design`");
  if (w.text == "time" && !ctx.tokens.empty())
    return std::string("**time** — the simulation time in seconds (in a boundary's T, a source's "
                       "power and their case overrides)");
  if (w.text == "mean" && ctx.tokens.size() == 2 && element_catalog().find(ctx.tokens.front()))
    return std::string("**mean**(NODE, ...) — the sensor reads the mean temperature of these "
                       "nodes");
  if (ctx.block != "case") return std::nullopt;
  if (w.text == "data" && ctx.tokens == std::vector<std::string>{"initial", "="})
    return std::string("**initial = data** — every node measured in the case starts at its first "
                       "measured value, every other node without a `T0` at the steady state "
                       "around them at t = 0");
  if (w.text == "range" && ctx.tokens.size() >= 3 && ctx.tokens[1] == "=" &&
      ctx.tokens.front().ends_with(".T0"))
    return fmt::format("**range** — the start temperature of `{}` is calibrated in this case "
                       "(`{}@CASE` in the reports of calibrate, diagnose and sensitivity)",
                       ctx.tokens.front().substr(0, ctx.tokens.front().size() - 3),
                       ctx.tokens.front());
  return std::nullopt;
}

/// The markdown of a submodel definition: its terminals and params.
std::optional<std::string> submodel_hover(const lang::Model& m, const std::string& name) {
  const lang::SubmodelDecl* sm = m.submodel(name);
  if (!sm) return std::nullopt;
  std::string terminals, params;
  for (const auto& t : sm->stmt->terminals)
    terminals += fmt::format("{}{}", terminals.empty() ? "" : ", ", t.name);
  for (const auto& v : sm->values)
    if (v.is_param) params += fmt::format("{}`{}`", params.empty() ? "" : ", ", v.name);
  return fmt::format("**{}** — submodel ({})\n\nparams: {}", name, terminals,
                     params.empty() ? "none" : params);
}

/// The markdown of a declared name.
std::optional<std::string> declaration_hover(const Document& doc, const std::string& name) {
  const lang::Model& m = doc.model();
  auto with_doc = [](std::string head, std::string_view d) {
    return d.empty() ? head : head + "\n\n" + std::string(d);
  };
  if (const lang::NodeDecl* n = find_node(m, name))
    return with_doc(fmt::format("**{}** — {}", name, n->boundary ? "boundary" : "node"), n->doc());
  for (const auto& v : m.values())
    if (v.name == name)
      return with_doc(fmt::format("**{}** — {}", name, v.is_param ? "param" : "const"), v.doc);
  if (const int i = m.element_index(name); i >= 0) {
    const lang::ElementDecl& e = m.elements()[static_cast<std::size_t>(i)];
    std::string kind = element_kind(m, name);
    std::string d = e.element && e.element->doc ? e.element->doc->text : "";
    return with_doc(fmt::format("**{}** — element of kind `{}`", name, kind), d);
  }
  for (const auto& c : m.cases())
    if (c.name == name) return fmt::format("**{}** — case", name);
  return std::nullopt;
}

} // namespace

nlohmann::json hover(const Document& doc, std::size_t at) {
  const std::string& text = doc.text();
  // A table or a data statement is described from the model's text, never from the file.
  std::optional<SpanText> about = table_hover(doc.model(), doc.root(), at);
  if (!about) about = data_statement_hover(doc.model(), doc.root(), at, text);
  if (about)
    return {{"contents", {{"kind", "markdown"}, {"value", about->markdown}}},
            {"range", range_json(text, about->begin, about->end)}};
  std::optional<CodeWord> cw = code_word_at(text, at);
  if (!cw) return nullptr;
  const Word* w = &cw->word;
  const StatementContext& ctx = cw->where;
  std::optional<std::string> md;
  const lang::ElementSchema* kind = element_catalog().find(w->text);
  // A key: `eps1 =`, `film.P =` in a case, or `lamp.P` read in a value.
  if (followed_by_assignment(text, *w) || (w->begin > 0 && text[w->begin - 1] == '.'))
    md = key_hover(doc, *cw);
  if (!md && kind && ctx.tokens.empty() && ctx.object.empty()) md = kind_markdown(*kind);
  if (!md) md = keyword_hover(*w, ctx);
  if (!md && loop_variable(text, *w)) md = fmt::format("**{}** — loop variable", w->text);
  if (!md) md = submodel_hover(doc.model(), w->text);
  if (!md && !(w->begin > 0 && text[w->begin - 1] == '.' && followed_by_assignment(text, *w)))
    if (std::string name = declared_name(doc.model(), qualified_name(text, *w)); !name.empty())
      md = declaration_hover(doc, name);
  if (!md && kind) md = kind_markdown(*kind);
  if (!md) return nullptr;
  return {{"contents", {{"kind", "markdown"}, {"value", *md}}},
          {"range", range_json(text, w->begin, w->end)}};
}

} // namespace thermnet::lsp
