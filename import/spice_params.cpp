#include "import/spice_params.hpp"

#include "import/fortran_number.hpp"
#include "import/spice_expression.hpp"
#include "import/spice_number.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

namespace thermnet::importer::spice {

void ParamScope::define(const std::string& name, ParamDef def) {
  if (!defs_.emplace(name, def).second)
    throw ImportError(def.at, "duplicate-name",
                      fmt::format("parameter '{}' is defined twice in one scope",
                                  lang::excerpt_for_display(name)));
}

std::optional<double> ParamScope::lookup(const std::string& name) const {
  if (auto v = values_.find(name); v != values_.end()) return v->second;
  if (auto d = defs_.find(name); d != defs_.end()) {
    if (!busy_.insert(name).second)
      throw ImportError(
          d->second.at, "param-cycle",
          fmt::format("parameter '{}' depends on itself", lang::excerpt_for_display(name)));
    double v = 0;
    try {
      v = spice::evaluate(d->second.text, d->second.file, d->second.offset,
                          [this](const std::string& n) { return lookup(n); });
    } catch (...) {
      busy_.erase(name);
      throw;
    }
    busy_.erase(name);
    values_[name] = v;
    return v;
  }
  return parent_ != nullptr ? parent_->lookup(name) : std::nullopt;
}

double ParamScope::evaluate(const ParamDef& def) const {
  return spice::evaluate(def.text, def.file, def.offset,
                         [this](const std::string& n) { return lookup(n); });
}

double ParamScope::value(const Token& t, bool* femto) const {
  if (t.kind == Token::Kind::expression)
    return spice::evaluate(t.text, t.at.file, t.text_offset,
                           [this](const std::string& n) { return lookup(n); });
  if (t.kind != Token::Kind::word)
    throw ImportError(
        t.at, "bad-syntax",
        fmt::format("expected a value, found '{}'", lang::excerpt_for_display(t.text)));
  if (auto n = spice_number(t.text)) {
    if (n->underflow) throw ImportError(t.at, "bad-number", underflow_message(t.text));
    if (femto != nullptr) *femto = n->femto_alone;
    return n->value;
  }
  if (auto v = lookup(lower(t.text))) return *v;
  throw ImportError(t.at, "bad-number",
                    fmt::format("'{}' is neither a number (e.g. 4.7k, 10u, 1e-3) nor a parameter",
                                lang::excerpt_for_display(t.text)));
}

ParamDef ParamScope::definition(const lang::SourceManager& sources,
                                const std::vector<Token>& tokens, std::size_t first,
                                std::size_t last) {
  const Token& a = tokens[first];
  const Token& b = tokens[last - 1];
  if (last - first == 1 && a.kind == Token::Kind::expression)
    return {a.text, a.at.file, a.text_offset, a.at};
  const lang::Span whole{a.at.file, a.at.begin, b.at.end};
  if (a.at.file == b.at.file && b.at.end >= a.at.begin) {
    const std::string_view raw =
        std::string_view(sources.text(a.at.file)).substr(a.at.begin, b.at.end - a.at.begin);
    if (raw.find('\n') == std::string_view::npos) {
      std::string text(raw);
      // Braces or quotes inside are the expression's own delimiters.
      for (char& c : text)
        if (c == '{' || c == '}' || c == '\'') c = ' ';
      return {text, a.at.file, a.at.begin, whole};
    }
  }
  std::string text;
  for (std::size_t i = first; i < last; ++i)
    text += (i > first ? " " : "") + tokens[i].text;
  return {text, a.at.file, a.at.begin, whole};
}

void read_assignments(const lang::SourceManager& sources, const std::vector<Token>& tokens,
                      std::size_t from, std::vector<std::pair<std::string, ParamDef>>& out) {
  std::size_t i = from;
  while (i < tokens.size()) {
    if (tokens[i].kind != Token::Kind::word || i + 2 > tokens.size() ||
        tokens[i + 1].kind != Token::Kind::equals)
      throw ImportError(tokens[i].at, "bad-syntax",
                        fmt::format("expected NAME = VALUE, found '{}'",
                                    lang::excerpt_for_display(tokens[i].text)));
    std::size_t j = i + 2;
    // The value runs to the next `NAME =`.
    while (j < tokens.size() && !(j + 1 < tokens.size() && tokens[j].kind == Token::Kind::word &&
                                  tokens[j + 1].kind == Token::Kind::equals && j > i + 2))
      ++j;
    if (j == i + 2)
      throw ImportError(
          tokens[i + 1].at, "bad-syntax",
          fmt::format("'{}' has no value", lang::excerpt_for_display(tokens[i].text)));
    out.emplace_back(lower(tokens[i].text), ParamScope::definition(sources, tokens, i + 2, j));
    i = j;
  }
}

} // namespace thermnet::importer::spice
