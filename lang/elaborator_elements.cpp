// The elaborator's nodes and elements: the built-in statements' schemas, an element's keys
// checked against its kind's schema, nodes, elements and composites.

#include "lang/elaborator.hpp"
#include "lang/elaborator_detail.hpp"

#include <boost/container/small_vector.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace thermnet::lang {
using namespace detail;

KeySchema detail::builtin_key(std::string name, Dimension d, bool min_exclusive, std::string doc) {
  KeySchema k;
  k.name = std::move(name);
  k.dim = d;
  k.min = 0.0;
  k.min_exclusive = min_exclusive;
  k.doc = std::move(doc);
  return k;
}

KeySchema detail::temperature_key(std::string name, std::string doc) {
  KeySchema k = builtin_key(std::move(name), dim::temperature, true, std::move(doc));
  k.absolute_temperature = true;
  return k;
}

// Schemas of the built-in statements, so nodes and boundaries are checked like element keys.
const ElementSchema& node_schema() {
  static const ElementSchema s = [] {
    ElementSchema e;
    e.kind = "node";
    e.terminals = 0;
    KeySchema c =
        builtin_key("C", dim::capacity, false, "heat capacity [J/K]; 0 for an arithmetic node");
    c.required = true;
    e.keys.push_back(std::move(c));
    e.keys.push_back(temperature_key("T0", "initial temperature [degC]"));
    return e;
  }();
  return s;
}

const ElementSchema& boundary_schema() {
  static const ElementSchema s = [] {
    ElementSchema e;
    e.kind = "boundary";
    e.terminals = 0;
    KeySchema t = temperature_key("T", "prescribed temperature [degC], or a signal");
    t.type = KeyType::signal;
    t.required = true;
    e.keys.push_back(std::move(t));
    return e;
  }();
  return s;
}

bool Elaborator::fill_keys(const ElementSchema& schema, ast::KeyList keys, FileId f, Span at,
                           const std::function<std::string()>& owner, ElementSpec& out) {
  bool ok = true;
  // Keys given so far with their spans (a handful per element: a flat list beats a map, and
  // kept inline it costs no allocation).
  boost::container::small_vector<std::pair<std::string_view, Span>, 8> given;
  std::size_t defaults = 0; // room for the keys given and the defaults filled in, at most
  for (const auto& ks : schema.keys)
    defaults += ks.default_value ? 1 : 0;
  out.values.reserve(out.values.size() + keys.size() + defaults);
  const auto find_given = [&](std::string_view name) -> const Span* {
    for (const auto& [key, span] : given)
      if (key == name) return &span;
    return nullptr;
  };
  for (const auto& kv : keys) {
    const KeySchema* ks = schema.key(kv.key.name);
    if (!ks) {
      Diagnostic d = DiagnosticEngine::make(DiagId::unknown_key, at, span_of(f, kv.key),
                                            schema.terminals == 0
                                                ? fmt::format("{} '{}'", schema.kind, out.name)
                                                : fmt::format("element kind '{}'", schema.kind),
                                            kv.key.name);
      if (auto s = closest_match(std::string(kv.key.name), schema.key_names()))
        d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
      else
        d.notes.push_back(DiagnosticEngine::note(
            DiagId::note_text, std::nullopt,
            fmt::format("'{}' takes: {}", schema.kind, list_names(schema.key_names()))));
      report(std::move(d));
      ok = false;
      continue;
    }
    if (find_given(kv.key.name)) {
      report(DiagnosticEngine::make(DiagId::duplicate_key, at, span_of(f, kv.key), kv.key.name));
      ok = false;
      continue;
    }
    given.emplace_back(kv.key.name, span_of(f, kv.key));
    Place place{[&] { return fmt::format("{} of {}", ks->name, owner()); }, ks->dim,
                ks->absolute_temperature, ks, ks->type == KeyType::signal};
    if (ks->type == KeyType::node) {
      const ast::Identifier* id = as_identifier(kv.value, m_.file(f));
      const ast::Ref* ref = kv.value.as_reference();
      if (!id && !ref) {
        report(DiagnosticEngine::make(DiagId::syntax_expected, at, span_of(f, kv),
                                      fmt::format("expected a node name for {}", place.what())));
        ok = false;
        continue;
      }
      ast::Ref plain;
      if (id) {
        plain.id = *id;
        plain.begin = id->begin;
        plain.end = id->end;
      }
      if (auto n = resolve_node(ref ? *ref : plain, f, context_, at))
        out.add_node_key(*ks, *n);
      else
        ok = false;
      continue;
    }
    if (ks->type == KeyType::number && !kv.value.as_expr()) {
      report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, span_of(f, kv), place.what()));
      ok = false;
      continue;
    }
    if (auto s = signal(kv.value, f, place, at, out.name))
      out.values[*ks] = std::move(*s);
    else
      ok = false;
  }
  const std::string& kind_word = schema.kind;
  // Exactly one alternative group (e.g. radiation: GR, or A + eps1 + eps2) must be given in full.
  const auto in_groups = [&](const std::string& name) {
    for (const auto& g : schema.alternatives)
      if (std::find(g.begin(), g.end(), name) != g.end()) return true;
    return false;
  };
  if (!schema.alternatives.empty()) {
    const std::vector<std::string>* first_touched = nullptr;
    std::size_t touched = 0;
    for (const auto& g : schema.alternatives) {
      bool any = false;
      for (const auto& k : g)
        any |= find_given(k) != nullptr;
      for (const auto& ks : schema.keys) // optional parts of the group (radiation: F)
        any |= !ks.with.empty() && std::find(g.begin(), g.end(), ks.with) != g.end() &&
               find_given(ks.name) != nullptr;
      if (any && touched++ == 0) first_touched = &g;
    }
    // "GR, or A, eps1 and eps2": formed only for a message.
    const auto options = [&] {
      std::string out;
      for (const auto& g : schema.alternatives) {
        std::string names;
        for (std::size_t i = 0; i < g.size(); ++i)
          names += (i == 0 ? "" : i + 1 == g.size() ? " and " : ", ") + g[i];
        out += (out.empty() ? "" : ", or ") + names;
      }
      return out;
    };
    if (touched == 0) {
      report(DiagnosticEngine::make(DiagId::missing_keys, at, std::nullopt, kind_word, out.name,
                                    options()));
      ok = false;
    } else if (touched > 1) {
      report(DiagnosticEngine::make(DiagId::conflicting_keys, at, std::nullopt,
                                    fmt::format("{} '{}' takes either {}, not several of them",
                                                kind_word, out.name, options())));
      ok = false;
    } else {
      for (const auto& k : *first_touched)
        if (!find_given(k)) {
          report(DiagnosticEngine::make(DiagId::missing_key, at, std::nullopt, kind_word, out.name,
                                        k));
          ok = false;
        }
    }
  }
  for (const auto& ks : schema.keys) {
    if (find_given(ks.name)) continue;
    if (ks.default_value)
      out.values[ks] = Signal::of(*ks.default_value);
    else if (ks.required && !in_groups(ks.name)) {
      report(DiagnosticEngine::make(DiagId::missing_key, at, std::nullopt, kind_word,
                                    out.name.empty() ? owner() : out.name, ks.name));
      ok = false;
    }
  }
  if (ok && schema.check)
    for (const auto& problem : schema.check(out.key_values())) {
      const Span* g = find_given(problem.key);
      report(DiagnosticEngine::make(DiagId::conflicting_keys, at,
                                    g ? std::optional<Span>(*g) : std::nullopt,
                                    fmt::format("{}: {}", owner(), problem.message)));
      ok = false;
    }
  return ok;
}

void Elaborator::elaborate_node(const NodeDecl& d, NodeSpec& out) {
  Restore<const Scope*> context(context_, d.scope);
  out.name = d.name;
  out.boundary = d.boundary;
  out.set_doc(d.doc());
  out.where = d.where();
  ElementSpec tmp;
  tmp.name = d.name;
  const ElementSchema& schema = d.boundary ? boundary_schema() : node_schema();
  Span at{d.file, d.where().begin, d.where().begin};
  fill_keys(
      schema, d.keys(), d.file, at, [&] { return fmt::format("{} '{}'", schema.kind, d.name); },
      tmp);
  if (d.boundary) {
    if (tmp.has("T")) out.T = std::move(tmp.values.at("T"));
  } else {
    if (tmp.has("C")) out.C = tmp.number("C");
    if (tmp.has("T0")) out.T0 = tmp.number("T0");
  }
}

std::optional<ElementSpec> Elaborator::elaborate_element(const ElementDecl& d) {
  if (!d.valid) return std::nullopt; // its kind or terminals are wrong: reported at load
  Restore<const Scope*> context(context_, d.scope);
  const ast::ElementStmt& s = *d.element;
  FileId f = d.file;
  Span at{f, s.begin, s.begin};
  ElementSpec e;
  e.schema = d.schema;
  e.name = d.name;
  e.where = d.where();
  e.set_nodes(d.nodes);
  const std::span<const int> nodes = e.nodes();
  bool ok = std::find(nodes.begin(), nodes.end(), -1) == nodes.end();
  ok &= fill_keys(
      *d.schema, s.keys, f, at, [&] { return fmt::format("{} '{}'", e.kind(), e.name); }, e);
  if (!ok) return std::nullopt;
  const auto& decls = m_.nodes();
  if (d.schema->observes) return e; // a sensor reads its nodes, boundaries included
  if (nodes.size() == 2 && nodes[0] == nodes[1]) {
    report(DiagnosticEngine::make(DiagId::self_link, at, span_of(f, s.nodes[1]), e.name,
                                  decls[static_cast<std::size_t>(nodes[0])].name));
    return std::nullopt;
  }
  if (d.schema->is_source)
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (decls[static_cast<std::size_t>(nodes[i])].boundary) {
        report(DiagnosticEngine::make(DiagId::heater_on_boundary, at, span_of(f, s.nodes[i]),
                                      e.kind(), e.name,
                                      decls[static_cast<std::size_t>(nodes[i])].name));
        return std::nullopt;
      }
  if (nodes.size() == 2 && decls[static_cast<std::size_t>(nodes[0])].boundary &&
      decls[static_cast<std::size_t>(nodes[1])].boundary)
    report(DiagnosticEngine::make(DiagId::both_boundaries, at, span_of(f, s.name), e.name));
  return e;
}

std::optional<ElementSpec> Elaborator::elaborate_composite(const ElementDecl& d) {
  Restore<const Scope*> context(context_, d.scope);
  const ast::CompositeStmt& s = *d.composite;
  FileId f = d.file;
  Span at{f, s.begin, s.begin};
  ElementSpec e;
  e.name = d.name;
  e.where = d.where();
  e.set_composite(s.mode.name == "series" ? Composite::series : Composite::parallel);
  e.set_nodes(d.nodes); // a series/parallel statement has two terminals (the grammar's)
  const std::span<const int> nodes = e.nodes();
  bool ok = std::find(nodes.begin(), nodes.end(), -1) == nodes.end();
  if (s.parts.empty()) {
    report(DiagnosticEngine::make(DiagId::composite_kind, at, span_of(f, s.name),
                                  fmt::format("{} '{}' has no inner elements", e.kind(), e.name)));
    ok = false;
  }
  for (const auto& part : s.parts) {
    const ElementSchema* schema = m_.catalog().find(part.kind.name);
    if (!schema) {
      Diagnostic diag =
          DiagnosticEngine::make(DiagId::unknown_kind, at, span_of(f, part.kind), part.kind.name);
      if (auto k = closest_match(std::string(part.kind.name), m_.catalog().kinds()))
        diag.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *k));
      report(std::move(diag));
      ok = false;
      continue;
    }
    if (schema->terminals != 2 || (e.composite() == Composite::series && !schema->conductance)) {
      report(DiagnosticEngine::make(
          DiagId::composite_kind, at, span_of(f, part.kind),
          schema->terminals != 2
              ? fmt::format("'{}' is not a two-terminal element and cannot be part of a {} block",
                            part.kind.name, e.kind())
              : fmt::format("'{}' is not a linear conductance, so it cannot be added as a "
                            "resistance in a series block (use a node between the parts)",
                            part.kind.name)));
      ok = false;
      continue;
    }
    ElementSpec p;
    p.schema = schema;
    p.set_nodes(nodes);
    ok &= fill_keys(
        *schema, part.keys, f, at,
        [&] { return fmt::format("{} in {} '{}'", part.kind.name, e.kind(), e.name); }, p);
    e.edit_parts().push_back(std::move(p));
  }
  if (!ok) return std::nullopt;
  if (nodes[0] == nodes[1]) {
    report(DiagnosticEngine::make(DiagId::self_link, at, span_of(f, s.nodes[1]), e.name,
                                  m_.nodes()[static_cast<std::size_t>(nodes[0])].name));
    return std::nullopt;
  }
  return e;
}

// Param overrides of the case come first: every value may depend on them.

} // namespace thermnet::lang
