#include "editors/lsp/completion.hpp"

#include "app/schema_text.hpp"
#include "editors/lsp/text_context.hpp"
#include "kernel/core/element_registry.hpp"
#include "lang/keywords.hpp"

#include <algorithm>
#include <set>

namespace thermnet::lsp {
using namespace app;
namespace {

// CompletionItemKind values of the protocol.
constexpr int item_variable = 6;
constexpr int item_class = 7;
constexpr int item_property = 10;
constexpr int item_keyword = 14;
constexpr int item_constant = 21;

/// Collects items, once per label, keeping those that start with the typed prefix.
class Items {
public:
  explicit Items(std::string prefix) : prefix_(std::move(prefix)) {}
  void add(const std::string& label, int kind, const std::string& detail,
           const std::string& doc = {}, const std::string& insert = {}) {
    if (label.compare(0, prefix_.size(), prefix_) != 0 || !seen_.insert(label).second) return;
    nlohmann::json item = {{"label", label}, {"kind", kind}, {"detail", detail}};
    if (!doc.empty()) item["documentation"] = {{"kind", "markdown"}, {"value", doc}};
    if (!insert.empty()) item["insertText"] = insert;
    list_.push_back(std::move(item));
  }
  nlohmann::json take() { return std::move(list_); }

private:
  std::string prefix_;
  std::set<std::string> seen_;
  nlohmann::json list_ = nlohmann::json::array();
};

void add_kinds(Items& items, bool linear_only) {
  const auto& registry = element_catalog();
  for (const auto& kind : registry.kinds()) {
    const lang::ElementSchema* s = registry.find(kind);
    if (linear_only && !s->conductance) continue;
    items.add(kind, item_class, s->doc, kind_markdown(*s));
  }
}

void add_nodes(Items& items, const lang::Model& m) {
  for (const auto& n : m.nodes())
    items.add(std::string(n.name), item_variable, n.boundary ? "boundary" : "node",
              std::string(n.doc()));
}

void add_values(Items& items, const lang::Model& m) {
  for (const auto& v : m.values())
    items.add(v.name, item_constant, v.is_param ? "param" : "const", v.doc);
}

/// Keys of a kind not given yet in the statement.
void add_keys(Items& items, const std::string& kind, const std::vector<std::string>& given) {
  auto fresh = [&](const std::string& k) {
    return std::find(given.begin(), given.end(), k) == given.end();
  };
  if (const lang::ElementSchema* s = element_catalog().find(kind)) {
    for (const auto& k : s->keys)
      if (fresh(k.name)) items.add(k.name, item_property, key_unit(k), key_markdown(*s, k));
    return;
  }
  for (const auto& [name, doc] : builtin_keys(kind))
    if (fresh(name)) items.add(name, item_property, doc);
}

/// The submodels, offered where an element kind may stand.
void add_submodels(Items& items, const lang::Model& m) {
  for (const auto& sm : m.submodels())
    items.add(sm.name, item_class, "submodel");
}

/// The next part of the names inside an instance: after `u1.`, `pcb` for `u1.pcb`.
void add_inner_names(Items& items, const lang::Model& m, const std::string& object) {
  const std::string prefix = object + ".";
  auto add = [&](const std::string& name, const std::string& detail) {
    if (!name.starts_with(prefix)) return;
    std::string rest = name.substr(prefix.size());
    items.add(rest.substr(0, rest.find('.')), item_variable, detail);
  };
  for (const auto& n : m.nodes())
    add(std::string(n.name), n.boundary ? "boundary" : "node");
  for (const auto& e : m.elements())
    add(std::string(e.name), "element");
}

/// Completions inside a value: node names for node keys, else params and consts.
void add_value_items(Items& items, const lang::Model& m, const std::string& kind,
                     const std::string& key) {
  if (const lang::ElementSchema* s = element_catalog().find(kind))
    if (const lang::KeySchema* k = s->key(key); k && k->type == lang::KeyType::node) {
      add_nodes(items, m);
      return;
    }
  if (key == "initial") {
    items.add("steady", item_keyword, "start from the steady state");
    items.add("data", item_keyword,
              "measured nodes start at their first measured value, the others at the steady state "
              "around them");
  }
  items.add("time", item_keyword, "the simulation time [s] (in a boundary's T or a power)");
  add_values(items, m);
}

/// The options of a table or data statement not written yet (`time` and `separator` are
/// completed with their ` = `).
void add_file_options(Items& items, const std::vector<std::string>& given, bool hold) {
  auto fresh = [&](const char* o) {
    return std::find(given.begin(), given.end(), o) == given.end();
  };
  if (hold && fresh("hold"))
    items.add("hold", item_keyword, "each row's value holds until the next row (a switch)");
  if (fresh("time"))
    items.add("time", item_keyword, "time = \"COLUMN\" [UNIT]: the time column and its unit",
              "`[s]`, `[min]`, `[h]`, `[day]`, `[unix s]`, `[unix ms]`, `[unix us]`, `[unix ns]` "
              "or `[iso]`",
              "time = ");
  if (fresh("separator"))
    items.add("separator", item_keyword, "separator = \";\": the field separator (\",\" if none)",
              {}, "separator = ");
}

/// The options written in a token list (`hold`, and `time`/`separator` followed by `=`).
std::vector<std::string> options_given(const std::vector<std::string>& tokens, std::size_t from) {
  std::vector<std::string> out;
  for (std::size_t k = from; k < tokens.size(); ++k)
    if (tokens[k] == "hold" || ((tokens[k] == "time" || tokens[k] == "separator") &&
                                k + 1 < tokens.size() && tokens[k + 1] == "="))
      out.push_back(tokens[k]);
  return out;
}

/// Completions inside the arguments of a `table(` the cursor stands in, if it stands in one:
/// `data` for the file, the options after the column; nothing where a string goes (the files a
/// model names are never read to offer their columns).
bool table_argument_items(Items& items, const std::vector<std::string>& tokens) {
  int depth = 0;
  for (std::size_t i = tokens.size(); i-- > 0;) {
    if (tokens[i] == ")") {
      ++depth;
    } else if (tokens[i] == "(" && depth > 0) {
      --depth;
    } else if (tokens[i] == "(") {
      if (i == 0 || tokens[i - 1] != "table") return false;
      std::size_t commas = 0;
      int d = 0;
      for (std::size_t k = i + 1; k < tokens.size(); ++k) {
        if (tokens[k] == "(") ++d;
        if (tokens[k] == ")") --d;
        if (d == 0 && tokens[k] == ",") ++commas;
      }
      if (tokens.back() == "(")
        items.add("data", item_keyword, "the case's own data file");
      else if (commas >= 2 && tokens.back() == ",")
        add_file_options(items, options_given(tokens, i + 1), true);
      return true;
    }
  }
  return false;
}

/// Completions in a data statement: its options after the file; in its column map, the nodes,
/// boundaries and sensors as targets and `mean` after `=`.
void data_items(Items& items, const lang::Model& m, const StatementContext& ctx) {
  if (ctx.block == "data") { // inside the column map
    if (ctx.tokens.empty()) {
      add_nodes(items, m);
      for (const auto& e : m.elements())
        if (const lang::ElementSchema* s = element_catalog().find(element_kind(m, e.name));
            s && s->observes)
          items.add(std::string(e.name), item_variable, "sensor");
    } else if (ctx.tokens.size() == 2 && ctx.tokens.back() == "=") {
      items.add("mean", item_keyword, "mean(a, b) or mean(a: 2, b: 1): the mean of columns");
    }
    return;
  }
  if (ctx.tokens.size() >= 2 && !ctx.value_position())
    add_file_options(items, options_given(ctx.tokens, 1), false);
}

/// Completions inside a case block.
void case_items(Items& items, const lang::Model& m, const StatementContext& ctx) {
  if (ctx.block == "data" || (!ctx.tokens.empty() && ctx.tokens.front() == "data")) {
    data_items(items, m, ctx);
    return;
  }
  if (ctx.value_position()) {
    add_value_items(items, m, "case", ctx.current_key());
    return;
  }
  // NODE.T0 = VALUE: the start temperature may be calibrated in this case
  if (ctx.tokens.size() >= 3 && ctx.tokens[1] == "=" && ctx.tokens.front().ends_with(".T0")) {
    items.add("range", item_keyword, "range LO .. HI: a start temperature calibrated in the case");
    return;
  }
  if (!ctx.tokens.empty()) return;
  add_keys(items, "case", {});
  items.add("for", item_keyword, "repeat overrides over a range");
  for (const auto& e : m.elements())
    items.add(std::string(e.name), item_variable, "element " + element_kind(m, e.name));
  add_nodes(items, m);
  for (const auto& v : m.values())
    if (v.is_param) items.add(v.name, item_constant, "param", v.doc);
}

} // namespace

nlohmann::json completion(const Document& doc, std::size_t at) {
  const lang::Model& m = doc.model();
  StatementContext ctx = context_at(doc.text(), at);
  Items items(ctx.partial);
  if (ctx.in_comment || ctx.in_string) return items.take();

  if (!ctx.object.empty()) { // `film.` in a case: the object's keys
    if (const lang::NodeDecl* n = find_node(m, ctx.object))
      add_keys(items, n->boundary ? "boundary" : "node", {});
    else if (std::string kind = element_kind(m, ctx.object); !kind.empty())
      add_keys(items, kind, {});
    else
      add_inner_names(items, m, ctx.object); // `u1.` of an instance
    return items.take();
  }
  if (table_argument_items(items, ctx.tokens)) return items.take();
  if (ctx.block == "case" || ctx.block == "data") {
    case_items(items, m, ctx);
    return items.take();
  }
  if (ctx.tokens.empty()) { // a statement's first word
    if (ctx.inner) {
      add_kinds(items, ctx.block == "series");
    } else {
      for (std::string_view k : lang::statement_keywords)
        items.add(std::string(k), item_keyword, "statement");
      items.add("for", item_keyword, "loop: for VAR in LO .. HI { ... }");
      items.add("submodel", item_keyword, "a reusable part: submodel NAME(TERMINAL, ...) { ... }");
      items.add("require", item_keyword,
                "a requirement: require band|gradient|power|energy|margin \"GROUP\" ...");
      add_kinds(items, false);
      add_submodels(items, m);
    }
    return items.take();
  }

  const std::string& first = ctx.tokens.front();
  const lang::ElementSchema* schema = element_catalog().find(first);
  // sensor NAME mean(NODE, ...): the nodes it averages
  if (schema && schema->observes && ctx.tokens.size() >= 4 && ctx.tokens[2] == "mean" &&
      ctx.tokens[3] == "(" &&
      std::find(ctx.tokens.begin(), ctx.tokens.end(), ")") == ctx.tokens.end()) {
    if (ctx.tokens.back() == "(" || ctx.tokens.back() == ",") add_nodes(items, m);
    return items.take();
  }
  if (ctx.value_position()) {
    add_value_items(items, m, first, ctx.current_key());
    return items.take();
  }
  const std::size_t positional = ctx.positional_count();
  const bool keys_started = positional < ctx.tokens.size();
  if (const lang::ElementSchema* s = schema) {
    // KIND NAME NODE... key = value ...; inside a block: KIND key = value ...
    const std::size_t terminals_end = ctx.inner ? 1 : 2 + static_cast<std::size_t>(s->terminals);
    if (!keys_started && !ctx.inner && positional >= 2 && positional < terminals_end) {
      add_nodes(items, m);
      if (s->observes) items.add("mean", item_keyword, "mean(a, b): the mean of several nodes");
    } else if (keys_started || positional >= terminals_end) { // after `mean(a, b)` too
      add_keys(items, first, ctx.given_keys());
    }
  } else if (first == "series" || first == "parallel") {
    if (positional == 2 || positional == 3) add_nodes(items, m);
  } else if (first == "node" || first == "boundary") {
    if (positional >= 2 || keys_started) add_keys(items, first, ctx.given_keys());
  }
  return items.take();
}

} // namespace thermnet::lsp
