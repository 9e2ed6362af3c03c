#include "editors/lsp/navigation.hpp"

#include "editors/lsp/json_text.hpp"
#include "editors/lsp/position.hpp"
#include "editors/lsp/text_context.hpp"
#include "editors/lsp/uri.hpp"

#include <algorithm>
#include <optional>

namespace thermnet::lsp {
namespace {

// SymbolKind values of the protocol.
constexpr int symbol_namespace = 3;
constexpr int symbol_class = 5;
constexpr int symbol_property = 7;
constexpr int symbol_variable = 13;
constexpr int symbol_constant = 14;
constexpr int symbol_object = 19;

/// A declaration: its file, statement and name spans, and how to show it.
struct Decl {
  lang::FileId file;
  lang::Span where;
  lang::Span name_span;
  std::string name;
  std::string detail;
  int kind;
};

std::vector<Decl> declarations(const lang::Model& m) {
  std::vector<Decl> out;
  for (const auto& v : m.values())
    out.push_back({v.file, v.where, v.name_span, v.name, v.is_param ? "param" : "const",
                   v.is_param ? symbol_property : symbol_constant});
  for (const auto& n : m.nodes())
    out.push_back({n.file, n.where(), n.name_span(), std::string(n.name),
                   n.boundary ? "boundary" : "node",
                   n.boundary ? symbol_constant : symbol_variable});
  for (const auto& e : m.elements()) {
    std::string kind(e.element     ? e.element->kind.name
                     : e.composite ? e.composite->mode.name
                                   : std::string_view());
    out.push_back({e.file, e.where(), e.name_span(), std::string(e.name), kind, symbol_object});
  }
  for (const auto& c : m.cases())
    out.push_back({c.file, c.where, c.name_span, c.name, "case", symbol_namespace});
  for (const auto& sm : m.submodels())
    out.push_back({sm.file, sm.where, sm.name_span, sm.name, "submodel", symbol_class});
  return out;
}

/// Whether `name` is the name of one of `decls`.
bool declared(const std::vector<Decl>& decls, std::string_view name) {
  return std::any_of(decls.begin(), decls.end(), [&](const Decl& d) { return d.name == name; });
}

/// declared_name() over a list of declarations.
std::string declared_name(const std::vector<Decl>& decls, const std::string& written) {
  if (written.empty() || declared(decls, written)) return written;
  const std::string inner = "." + written;
  for (const auto& d : decls)
    if (d.name.ends_with(inner)) return d.name;
  const std::size_t index = written.find('[');
  if (index == std::string::npos) return {};
  const std::string family = written.substr(0, index + 1);
  for (const auto& d : decls)
    if (d.name.starts_with(family)) return d.name;
  return {};
}

} // namespace

std::string declared_name(const lang::Model& m, const std::string& written) {
  // A name written in full is looked up in the model's indices; only a partial one (an inner
  // name of an instance, an indexed family) is searched for among all the declarations.
  const auto named = [&](const auto& decls) {
    return std::any_of(decls.begin(), decls.end(),
                       [&](const auto& d) { return d.name == written; });
  };
  if (m.node_index(written) >= 0 || m.element_index(written) >= 0 || named(m.values()) ||
      named(m.cases()) || m.submodel(written))
    return written;
  return declared_name(declarations(m), written);
}

nlohmann::json definition(const Document& doc, std::size_t at) {
  const std::string& text = doc.text();
  std::optional<CodeWord> cw = code_word_at(text, at);
  if (!cw) return nullptr;
  const Word* w = &cw->word;
  const StatementContext& ctx = cw->where;
  if (w->begin > 0 && text[w->begin - 1] == '.' && followed_by_assignment(text, *w))
    return nullptr; // a key after `object.`
  if (auto v = loop_variable(text, *w))
    return {{"uri", doc.uri()}, {"range", range_json(text, *v, *v + w->text.size())}};
  // Values first (keys are not declarations), then nodes, elements, cases.
  std::vector<Decl> decls = declarations(doc.model());
  std::stable_sort(decls.begin(), decls.end(), [](const Decl& a, const Decl& b) {
    auto rank = [](const Decl& d) {
      return d.detail == "param" || d.detail == "const"     ? 0
             : d.detail == "node" || d.detail == "boundary" ? 1
             : d.kind == symbol_object                      ? 2
                                                            : 3;
    };
    return rank(a) < rank(b);
  });
  const bool declares_value =
      !ctx.tokens.empty() && (ctx.tokens.front() == "param" || ctx.tokens.front() == "const");
  if (followed_by_assignment(text, *w) && !ctx.tokens.empty() && !declares_value)
    return nullptr; // `key = ...` of an element, node or boundary
  const std::string name = declared_name(decls, qualified_name(text, *w));
  for (const auto& d : decls) {
    if (d.name != name) continue;
    const auto& sources = doc.sources();
    std::string uri = d.file == doc.root() ? doc.uri() : path_to_uri(sources.path(d.file));
    return {{"uri", uri},
            {"range", range_json(sources.text(d.file), d.name_span.begin, d.name_span.end)}};
  }
  return nullptr;
}

std::string document_symbols_text(const Document& doc) {
  std::vector<Decl> decls = declarations(doc.model());
  std::erase_if(decls, [&](const Decl& d) { return d.file != doc.root(); });
  std::stable_sort(decls.begin(), decls.end(),
                   [](const Decl& a, const Decl& b) { return a.where.begin < b.where.begin; });
  std::string out = "[";
  out.reserve(decls.size() * 200); // an item takes about 150 bytes
  const LineIndex& lines = doc.lines();
  for (const auto& d : decls) {
    std::uint32_t begin = std::min(d.where.begin, d.name_span.begin);
    std::uint32_t end = std::max(d.where.end, d.name_span.end);
    out += out.size() == 1 ? "{\"detail\":" : ",{\"detail\":";
    append_json_string(out, d.detail);
    out += ",\"kind\":" + std::to_string(d.kind) + ",\"name\":";
    append_json_string(out, d.name);
    out += ",\"range\":";
    lines.append_range(out, begin, end);
    out += ",\"selectionRange\":";
    lines.append_range(out, d.name_span.begin, d.name_span.end);
    out += '}';
  }
  out += ']';
  return out;
}

} // namespace thermnet::lsp
