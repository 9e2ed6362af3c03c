#include "lang/elaborator.hpp"

#include "lang/csv.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace thermnet::lang {
namespace {

namespace fs = std::filesystem;

/// A key of a built-in statement: name, dimension, lower bound 0 (exclusive or not), doc.
KeySchema builtin_key(std::string name, Dimension d, bool min_exclusive, std::string doc) {
  KeySchema k;
  k.name = std::move(name);
  k.dim = d;
  k.min = 0.0;
  k.min_exclusive = min_exclusive;
  k.doc = std::move(doc);
  return k;
}

/// A temperature key: bare numbers in degC, above absolute zero.
KeySchema temperature_key(std::string name, std::string doc) {
  KeySchema k = builtin_key(std::move(name), dim::temperature, true, std::move(doc));
  k.absolute_temperature = true;
  return k;
}

/// Schemas of the built-in statements, so nodes and boundaries are checked like element keys.
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

/// The identifier a value consists of, if it is a bare name.
const ast::Identifier* as_identifier(const ast::Value& v) {
  const auto* e = boost::get<ast::Expr>(&v);
  if (!e || !e->rest.empty() || !e->first.rest.empty()) return nullptr;
  const ast::Signed& s = e->first.first;
  if (!s.signs.empty() || !s.power.tail.empty()) return nullptr;
  return boost::get<ast::Identifier>(&s.power.base);
}

Span span_of(FileId f, const ast::Tagged& t) {
  return Span{f, t.begin, t.end};
}

std::string list_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < 4; ++i)
    out += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > 4) out += fmt::format(" and {} more", names.size() - 4);
  return out;
}

} // namespace

Elaborator::Elaborator(const Model& model, Reporter report, const CaseDecl* c,
                       const ParamValues& overrides, bool check_data)
    : m_(model), report_(std::move(report)), case_(c),
      overrides_(overrides.begin(), overrides.end()), check_data_(check_data) {
  for (const auto& v : m_.values())
    value_decls_.emplace(v.name, &v);
}

void Elaborator::report(Diagnostic d) {
  report_(std::move(d));
}

Evaluator Elaborator::evaluator(FileId f) {
  return Evaluator(f, [this](const ast::Identifier& id, FileId file) {
    used_.insert(id.name);
    return value_of(id.name, span_of(file, id));
  });
}

Quantity Elaborator::value_of(const std::string& name, Span use) {
  auto decl_it = value_decls_.find(name);
  if (decl_it == value_decls_.end()) {
    if (m_.declared_by_unparsed(name)) throw EvalError(Diagnostic{}); // its syntax error is out
    Diagnostic d = DiagnosticEngine::make(DiagId::unknown_name, use, use, name);
    std::vector<std::string> names;
    for (const auto& v : m_.values())
      names.push_back(v.name);
    if (auto s = closest_match(name, names))
      d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
    throw EvalError(std::move(d));
  }
  if (auto it = values_.find(name); it != values_.end()) {
    if (std::isnan(it->second.value)) throw EvalError(Diagnostic{}); // failed earlier, reported
    return it->second;
  }
  const ValueDecl& decl = *decl_it->second;
  Span at{decl.file, decl.where.begin, decl.where.begin};
  for (std::size_t i = 0; i < evaluating_.size(); ++i)
    if (evaluating_[i] == name) {
      std::string path;
      for (std::size_t k = i; k < evaluating_.size(); ++k)
        path += evaluating_[k] + " -> ";
      throw EvalError(DiagnosticEngine::make(DiagId::cycle, at, decl.name_span, name, path + name));
    }
  evaluating_.push_back(name);
  Quantity q;
  try {
    q = evaluator(decl.file).eval(*decl.expr);
  } catch (const EvalError& e) {
    evaluating_.pop_back();
    values_[name] = Quantity{std::nan(""), std::nullopt};
    if (e.diag.code.empty()) throw;
    Diagnostic d = e.diag;
    // Errors inside a declaration are located at that declaration, and reported once there.
    if (d.at && d.at->file == decl.file && d.at->begin >= decl.where.begin &&
        d.at->begin <= decl.where.end)
      d.at = at;
    report(std::move(d));
    throw EvalError(Diagnostic{});
  }
  // The name stays on the evaluation stack while its range is evaluated, so that a range that
  // refers to the param itself (`param p = 1 range 0 .. p`) is a cycle, not endless recursion.
  if (decl.is_param && decl.range) {
    try {
      Evaluator ev = evaluator(decl.file);
      Quantity lo = ev.eval(decl.range->lo), hi = ev.eval(decl.range->hi);
      for (const Quantity* b : {&lo, &hi})
        if (b->dim && q.dim && !(*b->dim == *q.dim))
          report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_of(decl.file, *decl.range),
                                        fmt::format("the range of param '{}'", name),
                                        describe(*q.dim), describe(*b->dim)));
      if (!q.dim && lo.dim && hi.dim && !(*lo.dim == *hi.dim)) // (else checked against q above)
        report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_of(decl.file, *decl.range),
                                      fmt::format("the upper bound of param '{}'", name),
                                      describe(*lo.dim), describe(*hi.dim)));
      // A bare value takes the unit its range gives (temperatures excepted: bare ones are degC).
      if (const auto& b = lo.dim ? lo.dim : hi.dim; !q.dim && b && !(*b == dim::temperature))
        q.dim = b;
      if (!(lo.value < hi.value))
        report(DiagnosticEngine::make(DiagId::bad_range, at, span_of(decl.file, *decl.range), name,
                                      fmt::format("{:g}", lo.value),
                                      fmt::format("{:g}", hi.value)));
      else if (q.value < lo.value || q.value > hi.value)
        report(DiagnosticEngine::make(DiagId::param_outside_range, at,
                                      span_of(decl.file, *decl.expr), name,
                                      fmt::format("{:g}", q.value), fmt::format("{:g}", lo.value),
                                      fmt::format("{:g}", hi.value)));
      ranges_[name] = {lo.value, hi.value};
    } catch (const EvalError& e) {
      if (!e.diag.code.empty()) {
        Diagnostic d = e.diag;
        if (d.at && d.at->file == decl.file && d.at->begin >= decl.where.begin &&
            d.at->begin <= decl.where.end)
          d.at = at;
        report(std::move(d));
      }
    }
  }
  evaluating_.pop_back();
  if (auto o = overrides_.find(name); o != overrides_.end()) q.value = o->second;
  values_[name] = q;
  return q;
}

std::optional<double> Elaborator::to_place(const Quantity& q, const Place& p, Span at, Span mark) {
  if (q.dim && !(*q.dim == p.dim)) {
    report(DiagnosticEngine::make(DiagId::unit_mismatch, at, mark, p.what(), describe(p.dim),
                                  describe(*q.dim)));
    return std::nullopt;
  }
  double v = q.value;
  if (!q.dim && p.absolute_temperature) v += 273.15; // bare temperatures are degC
  if (!check_range(v, p, at, mark)) return std::nullopt;
  return v;
}

bool Elaborator::check_range(double v, const Place& p, Span at, Span mark) {
  if (!p.key || p.key->accepts(v)) return true;
  std::string range =
      p.key->absolute_temperature ? "above absolute zero (-273.15 degC)" : p.key->range_text();
  report(DiagnosticEngine::make(DiagId::out_of_range, at, mark, p.what(), range,
                                format_value(v, p.dim, p.absolute_temperature)));
  return false;
}

std::optional<double> Elaborator::number(const ast::Expr& e, FileId f, const Place& p, Span at) {
  try {
    return to_place(evaluator(f).eval(e), p, at, span_of(f, e));
  } catch (const EvalError& err) {
    if (err.diag.code.empty()) return std::nullopt;
    Diagnostic d = err.diag;
    d.at = at;
    report(std::move(d));
    return std::nullopt;
  }
}

std::optional<Signal> Elaborator::signal(const ast::Value& v, FileId f, const Place& p, Span at) {
  if (const auto* e = boost::get<ast::Expr>(&v)) {
    auto x = number(*e, f, p, at);
    return x ? std::optional<Signal>(Signal::of(*x)) : std::nullopt;
  }
  if (const auto* ps = boost::get<ast::PointSignal>(&v)) {
    Signal s;
    s.kind = ps->kind.name == "step" ? Signal::Kind::step : Signal::Kind::pwl;
    Place time{
        [&] { return fmt::format("a time in the {} signal of {}", ps->kind.name, p.what()); },
        dim::time};
    bool ok = true;
    for (const auto& pt : ps->points) {
      auto t = number(pt.time, f, time, at);
      auto x = number(pt.value, f, p, at);
      if (!t || !x) {
        ok = false;
        continue;
      }
      if (!s.t.empty() && !(*t > s.t.back())) {
        report(DiagnosticEngine::make(
            DiagId::bad_signal, at, span_of(f, pt.time),
            fmt::format("signal times must increase: {:g} s follows {:g} s", *t, s.t.back())));
        ok = false;
        continue;
      }
      s.t.push_back(*t);
      s.v.push_back(*x);
    }
    if (!ok) return std::nullopt;
    return s;
  }
  const auto& ts = boost::get<ast::TableSignal>(v);
  fs::path path(ts.file.text);
  if (path.is_relative()) path = fs::path(m_.directory_of(f)) / path;
  try {
    CsvTable table = read_csv(path.string());
    int col = table.column_index(ts.column.text);
    if (col < 0) {
      Diagnostic d = DiagnosticEngine::make(
          DiagId::bad_signal, at, span_of(f, ts.column),
          fmt::format("'{}' has no column '{}'", ts.file.text, ts.column.text));
      if (auto s = closest_match(ts.column.text, table.columns))
        d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
      report(std::move(d));
      return std::nullopt;
    }
    Signal s;
    s.kind = Signal::Kind::pwl;
    for (std::size_t r = 0; r < table.rows(); ++r) {
      double x = table.cells[static_cast<std::size_t>(col)][r];
      if (std::isnan(x)) continue;
      s.t.push_back(table.time()[r]);
      s.v.push_back(p.absolute_temperature ? x + 273.15 : x);
    }
    if (s.t.empty()) {
      report(DiagnosticEngine::make(
          DiagId::bad_signal, at, span_of(f, ts.column),
          fmt::format("column '{}' of '{}' has no values", ts.column.text, ts.file.text)));
      return std::nullopt;
    }
    for (double x : s.v)
      if (!check_range(x, p, at, span_of(f, ts))) return std::nullopt;
    return s;
  } catch (const CsvError& e) {
    report(DiagnosticEngine::make(e.row == 0 ? DiagId::data_unreadable : DiagId::data_format, at,
                                  span_of(f, ts.file), ts.file.text,
                                  e.row == 0
                                      ? std::string(e.what()).substr(path.string().size() + 2)
                                      : std::string(e.what())));
    return std::nullopt;
  }
}

std::optional<int> Elaborator::resolve_node(const ast::Identifier& id, FileId f, Span at) {
  if (const int i = m_.node_index(id.name); i >= 0) return i;
  if (m_.declared_by_unparsed(id.name)) return std::nullopt; // its syntax error is reported
  Diagnostic d = DiagnosticEngine::make(DiagId::unknown_node, at, span_of(f, id), id.name);
  std::vector<std::string> names;
  for (const auto& n : m_.nodes())
    names.push_back(n.name);
  if (auto s = closest_match(id.name, names))
    d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
  report(std::move(d));
  return std::nullopt;
}

bool Elaborator::fill_keys(const ElementSchema& schema, const std::vector<ast::KeyValue>& keys,
                           FileId f, Span at, const std::function<std::string()>& owner,
                           ElementSpec& out) {
  bool ok = true;
  // Keys given so far with their spans (a handful per element: a flat list beats a map).
  std::vector<std::pair<const std::string*, Span>> given;
  const auto find_given = [&](const std::string& name) -> const Span* {
    for (const auto& [key, span] : given)
      if (*key == name) return &span;
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
      if (auto s = closest_match(kv.key.name, schema.key_names()))
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
    given.emplace_back(&kv.key.name, span_of(f, kv.key));
    Place place{[&] { return fmt::format("{} of {}", ks->name, owner()); }, ks->dim,
                ks->absolute_temperature, ks};
    if (ks->type == KeyType::node) {
      const ast::Identifier* id = as_identifier(kv.value);
      if (!id) {
        report(DiagnosticEngine::make(DiagId::syntax_expected, at, span_of(f, kv),
                                      fmt::format("expected a node name for {}", place.what())));
        ok = false;
      } else if (auto n = resolve_node(*id, f, at)) {
        out.node_keys[ks->name] = *n;
      } else {
        ok = false;
      }
      continue;
    }
    if (ks->type == KeyType::number && !boost::get<ast::Expr>(&kv.value)) {
      report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, span_of(f, kv), place.what()));
      ok = false;
      continue;
    }
    if (auto s = signal(kv.value, f, place, at))
      out.values[ks->name] = std::move(*s);
    else
      ok = false;
  }
  std::string kind_word = schema.kind;
  // Exactly one alternative group (e.g. radiation: GR, or A + eps1 + eps2) must be given in full.
  const auto in_groups = [&](const std::string& name) {
    for (const auto& g : schema.alternatives)
      if (std::find(g.begin(), g.end(), name) != g.end()) return true;
    return false;
  };
  if (!schema.alternatives.empty()) {
    std::vector<const std::vector<std::string>*> touched;
    std::string options;
    for (const auto& g : schema.alternatives) {
      bool any = false;
      std::string names;
      for (std::size_t i = 0; i < g.size(); ++i) {
        any |= find_given(g[i]) != nullptr;
        names += (i == 0 ? "" : i + 1 == g.size() ? " and " : ", ") + g[i];
      }
      for (const auto& ks : schema.keys) // optional parts of the group (radiation: F)
        any |= !ks.with.empty() && std::find(g.begin(), g.end(), ks.with) != g.end() &&
               find_given(ks.name) != nullptr;
      options += (options.empty() ? "" : ", or ") + names;
      if (any) touched.push_back(&g);
    }
    if (touched.empty()) {
      report(DiagnosticEngine::make(DiagId::missing_keys, at, std::nullopt, kind_word, out.name,
                                    options));
      ok = false;
    } else if (touched.size() > 1) {
      report(DiagnosticEngine::make(DiagId::conflicting_keys, at, std::nullopt,
                                    fmt::format("{} '{}' takes either {}, not several of them",
                                                kind_word, out.name, options)));
      ok = false;
    } else {
      for (const auto& k : *touched.front())
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
      out.values[ks.name] = Signal::of(*ks.default_value);
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
  out.name = d.name;
  out.boundary = d.boundary;
  out.doc = d.doc;
  out.where = d.where;
  ElementSpec tmp;
  tmp.name = d.name;
  const ElementSchema& schema = d.boundary ? boundary_schema() : node_schema();
  Span at{d.file, d.where.begin, d.where.begin};
  fill_keys(
      schema, *d.keys, d.file, at, [&] { return fmt::format("{} '{}'", schema.kind, d.name); },
      tmp);
  if (d.boundary) {
    if (tmp.has("T")) out.T = tmp.values["T"];
  } else {
    if (tmp.has("C")) out.C = tmp.number("C");
    if (tmp.has("T0")) out.T0 = tmp.number("T0");
  }
}

std::optional<ElementSpec> Elaborator::elaborate_element(const ElementDecl& d) {
  const ast::ElementStmt& s = *d.element;
  FileId f = d.file;
  Span at{f, s.begin, s.begin};
  const ElementSchema* schema = m_.catalog().find(s.kind.name);
  if (!schema) {
    Diagnostic diag =
        DiagnosticEngine::make(DiagId::unknown_kind, at, span_of(f, s.kind), s.kind.name);
    if (auto k = closest_match(s.kind.name, m_.catalog().kinds()))
      diag.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *k));
    report(std::move(diag));
    return std::nullopt;
  }
  if (static_cast<int>(s.nodes.size()) != schema->terminals) {
    Span mark =
        s.nodes.empty() ? span_of(f, s.name) : Span{f, s.nodes.front().begin, s.nodes.back().end};
    report(DiagnosticEngine::make(DiagId::wrong_terminals, at, mark, s.kind.name, schema->terminals,
                                  s.nodes.size()));
    return std::nullopt;
  }
  ElementSpec e;
  e.schema = schema;
  e.kind = s.kind.name;
  e.name = s.name.name;
  e.where = d.where;
  bool ok = true;
  for (const auto& n : s.nodes) {
    if (auto i = resolve_node(n, f, at))
      e.nodes.push_back(*i);
    else
      ok = false;
  }
  ok &= fill_keys(
      *schema, s.keys, f, at, [&] { return fmt::format("{} '{}'", e.kind, e.name); }, e);
  if (!ok) return std::nullopt;
  const auto& decls = m_.nodes();
  if (e.nodes.size() == 2 && e.nodes[0] == e.nodes[1]) {
    report(DiagnosticEngine::make(DiagId::self_link, at, span_of(f, s.nodes[1]), e.name,
                                  s.nodes[0].name));
    return std::nullopt;
  }
  if (schema->is_source)
    for (std::size_t i = 0; i < e.nodes.size(); ++i)
      if (decls[static_cast<std::size_t>(e.nodes[i])].boundary) {
        report(DiagnosticEngine::make(DiagId::heater_on_boundary, at, span_of(f, s.nodes[i]),
                                      e.kind, e.name, s.nodes[i].name));
        return std::nullopt;
      }
  if (e.nodes.size() == 2 && decls[static_cast<std::size_t>(e.nodes[0])].boundary &&
      decls[static_cast<std::size_t>(e.nodes[1])].boundary)
    report(DiagnosticEngine::make(DiagId::both_boundaries, at, span_of(f, s.name), e.name));
  return e;
}

std::optional<ElementSpec> Elaborator::elaborate_composite(const ElementDecl& d) {
  const ast::CompositeStmt& s = *d.composite;
  FileId f = d.file;
  Span at{f, s.begin, s.begin};
  ElementSpec e;
  e.kind = s.mode.name;
  e.name = s.name.name;
  e.where = d.where;
  e.composite = s.mode.name == "series" ? Composite::series : Composite::parallel;
  bool ok = true;
  for (const auto& n : s.nodes) {
    if (auto i = resolve_node(n, f, at))
      e.nodes.push_back(*i);
    else
      ok = false;
  }
  if (s.parts.empty()) {
    report(DiagnosticEngine::make(DiagId::composite_kind, at, span_of(f, s.name),
                                  fmt::format("{} '{}' has no inner elements", e.kind, e.name)));
    ok = false;
  }
  for (const auto& part : s.parts) {
    const ElementSchema* schema = m_.catalog().find(part.kind.name);
    if (!schema) {
      Diagnostic diag =
          DiagnosticEngine::make(DiagId::unknown_kind, at, span_of(f, part.kind), part.kind.name);
      if (auto k = closest_match(part.kind.name, m_.catalog().kinds()))
        diag.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *k));
      report(std::move(diag));
      ok = false;
      continue;
    }
    if (schema->terminals != 2 || (e.composite == Composite::series && !schema->conductance)) {
      report(DiagnosticEngine::make(
          DiagId::composite_kind, at, span_of(f, part.kind),
          schema->terminals != 2
              ? fmt::format("'{}' is not a two-terminal element and cannot be part of a {} block",
                            part.kind.name, e.kind)
              : fmt::format("'{}' is not a linear conductance, so it cannot be added as a "
                            "resistance in a series block (use a node between the parts)",
                            part.kind.name)));
      ok = false;
      continue;
    }
    ElementSpec p;
    p.schema = schema;
    p.kind = part.kind.name;
    p.nodes = e.nodes;
    ok &= fill_keys(
        *schema, part.keys, f, at,
        [&] { return fmt::format("{} in {} '{}'", part.kind.name, e.kind, e.name); }, p);
    e.parts.push_back(std::move(p));
  }
  if (!ok) return std::nullopt;
  if (e.nodes[0] == e.nodes[1]) {
    report(DiagnosticEngine::make(DiagId::self_link, at, span_of(f, s.nodes[1]), e.name,
                                  s.nodes[0].name));
    return std::nullopt;
  }
  return e;
}

NetworkSpec Elaborator::run() {
  NetworkSpec net;
  net.model = m_.name();
  // Param overrides of the case come first: every value may depend on them.
  if (case_) {
    std::set<std::string> seen;
    for (const auto& item : case_->stmt->items) {
      const auto* a = boost::get<ast::CaseAssign>(&item);
      if (!a || a->target.member) continue;
      const std::string& name = a->target.object.name;
      if (name == "duration" || name == "initial" || name == "output") continue;
      Span at{case_->file, a->begin, a->begin};
      Span mark = span_of(case_->file, a->target);
      auto it = value_decls_.find(name);
      if (it == value_decls_.end() && m_.declared_by_unparsed(name)) continue;
      if (it == value_decls_.end()) {
        Diagnostic d = DiagnosticEngine::make(DiagId::unknown_element, at, mark, name);
        std::vector<std::string> names;
        for (const auto& v : m_.values())
          names.push_back(v.name);
        for (const std::string w : {"duration", "initial", "output"})
          names.push_back(w);
        if (auto s = closest_match(name, names))
          d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
        report(std::move(d));
        continue;
      }
      const ValueDecl& decl = *it->second;
      if (!decl.is_param || decl.range) {
        report(DiagnosticEngine::make(
            DiagId::override_fixed_only, at, mark,
            !decl.is_param ? fmt::format("'{}' is a const; a case can set params only", name)
                           : fmt::format("param '{}' has a range, so it is calibrated; a case can "
                                         "set fixed params only",
                                         name)));
        continue;
      }
      if (!seen.insert(name).second) {
        report(DiagnosticEngine::make(DiagId::duplicate_case_key, at, mark, case_->name, name));
        continue;
      }
      const auto* e = boost::get<ast::Expr>(&a->value);
      if (!e) {
        report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, mark,
                                      fmt::format("param '{}'", name)));
        continue;
      }
      try {
        Quantity declared = value_of(name, mark);
        Quantity q = evaluator(case_->file).eval(*e);
        if (q.dim && declared.dim && !(*q.dim == *declared.dim)) {
          report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_of(case_->file, *e),
                                        fmt::format("param '{}'", name), describe(*declared.dim),
                                        describe(*q.dim)));
          continue;
        }
        pending_params_[name] = q.value;
      } catch (const EvalError& err) {
        if (!err.diag.code.empty()) {
          Diagnostic d = err.diag;
          d.at = at;
          report(std::move(d));
        }
      }
    }
    for (const auto& [k, v] : pending_params_)
      overrides_[k] = v;
    values_.clear(); // values computed so far may have used the declared params
  }
  net.nodes.resize(m_.nodes().size());
  for (std::size_t i = 0; i < m_.nodes().size(); ++i)
    elaborate_node(m_.nodes()[i], net.nodes[i]);
  element_slot_.assign(m_.elements().size(), -1);
  for (std::size_t i = 0; i < m_.elements().size(); ++i) {
    const ElementDecl& d = m_.elements()[i];
    auto e = d.element ? elaborate_element(d) : elaborate_composite(d);
    if (!e) continue;
    element_slot_[i] = static_cast<int>(net.elements.size());
    net.elements.push_back(std::move(*e));
  }
  if (case_) apply_case(net);
  return net;
}

void Elaborator::apply_case(NetworkSpec& net) {
  CaseSettings& s = net.settings;
  s.name = case_->name;
  s.where = case_->where;
  FileId f = case_->file;
  std::set<std::string> seen;
  static const KeySchema positive_time = builtin_key("", dim::time, true, "");
  static const KeySchema absolute = temperature_key("", "");
  for (const auto& item : case_->stmt->items) {
    if (const auto* data = boost::get<ast::CaseData>(&item)) {
      Span at{f, data->begin, data->begin};
      if (!seen.insert("data").second) {
        report(DiagnosticEngine::make(DiagId::duplicate_case_key, at, span_of(f, *data), s.name,
                                      "data"));
        continue;
      }
      fs::path p(data->path.text);
      if (p.is_relative()) p = fs::path(m_.directory_of(f)) / p;
      s.data_path = p.lexically_normal().string();
      if (check_data_) check_data(net, s.data_path, at, span_of(f, data->path));
      continue;
    }
    const auto& a = boost::get<ast::CaseAssign>(item);
    Span at{f, a.begin, a.begin};
    if (a.target.member) {
      apply_override(net, a, f);
      continue;
    }
    const std::string& key = a.target.object.name;
    if (key != "duration" && key != "initial" && key != "output") continue; // params: done in run()
    if (!seen.insert(key).second) {
      report(DiagnosticEngine::make(DiagId::duplicate_case_key, at, span_of(f, a.target), s.name,
                                    key));
      continue;
    }
    const auto* e = boost::get<ast::Expr>(&a.value);
    if (!e) {
      report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, span_of(f, a.target),
                                    fmt::format("'{}' of case '{}'", key, s.name)));
      continue;
    }
    if (key == "initial") {
      const ast::Identifier* id = as_identifier(a.value);
      if (id && id->name == "steady" && !value_decls_.count("steady")) {
        s.initial_steady = true;
        continue;
      }
      s.initial = number(*e, f,
                         Place{[&] { return fmt::format("'initial' of case '{}'", s.name); },
                               dim::temperature, true, &absolute},
                         at);
    } else {
      auto v = number(*e, f,
                      Place{[&] { return fmt::format("'{}' of case '{}'", key, s.name); },
                            dim::time, false, &positive_time},
                      at);
      (key == "duration" ? s.duration : s.output) = v;
    }
  }
  if (!seen.count("duration"))
    report(DiagnosticEngine::make(DiagId::missing_duration, Span{f, s.where.begin, s.where.begin},
                                  case_->name_span, s.name));
  else if (data_times_)
    warn_data_beyond_duration(s);
}

void Elaborator::warn_data_beyond_duration(const CaseSettings& s) {
  const std::size_t after = rows_after(data_times_->table, *s.duration);
  if (after == 0) return;
  report(DiagnosticEngine::make(
      DiagId::data_beyond_duration, data_times_->at, data_times_->mark,
      fs::path(s.data_path).filename().string(),
      after == 1 ? std::string("1 row") : fmt::format("{} rows", after), s.name,
      fmt::format("{:g} s; last row at {:g} s", *s.duration, data_times_->table.time().back()),
      after == 1 ? "it is" : "they are"));
}

void Elaborator::apply_override(NetworkSpec& net, const ast::CaseAssign& a, FileId f) {
  Span at{f, a.begin, a.begin};
  const std::string& obj = a.target.object.name;
  const std::string& key = a.target.member->name;
  Span key_span = span_of(f, *a.target.member);
  if (const int n = m_.node_index(obj); n >= 0) {
    NodeSpec& node = net.nodes[static_cast<std::size_t>(n)];
    const ElementSchema& schema = node.boundary ? boundary_schema() : node_schema();
    const KeySchema* ks = schema.key(key);
    if (!ks) {
      Diagnostic d = DiagnosticEngine::make(DiagId::unknown_key, at, key_span,
                                            fmt::format("{} '{}'", schema.kind, obj), key);
      if (auto s = closest_match(key, schema.key_names()))
        d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
      else
        d.notes.push_back(DiagnosticEngine::note(
            DiagId::note_text, std::nullopt,
            fmt::format("'{}' takes: {}", schema.kind, list_names(schema.key_names()))));
      report(std::move(d));
      return;
    }
    Place p{[&] { return fmt::format("{} of {} '{}'", key, schema.kind, obj); }, ks->dim,
            ks->absolute_temperature, ks};
    if (ks->type == KeyType::number && !boost::get<ast::Expr>(&a.value)) {
      report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, key_span, p.what()));
      return;
    }
    auto v = signal(a.value, f, p, at);
    if (!v) return;
    if (key == "T")
      node.T = *v;
    else if (key == "C")
      node.C = v->constant;
    else
      node.T0 = v->constant;
    return;
  }
  const int decl = m_.element_index(obj);
  if (decl < 0 && m_.declared_by_unparsed(obj)) return;
  if (decl < 0) {
    Diagnostic d =
        DiagnosticEngine::make(DiagId::unknown_element, at, span_of(f, a.target.object), obj);
    std::vector<std::string> names;
    for (const auto& e : m_.elements())
      names.push_back(e.name);
    for (const auto& nd : m_.nodes())
      names.push_back(nd.name);
    if (auto s = closest_match(obj, names))
      d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
    report(std::move(d));
    return;
  }
  const ElementDecl& element_decl = m_.elements()[static_cast<std::size_t>(decl)];
  if (element_decl.composite) {
    report(
        DiagnosticEngine::make(DiagId::override_fixed_only, at, span_of(f, a.target),
                               fmt::format("the keys of {} '{}' belong to its inner elements and "
                                           "cannot be set by a case",
                                           element_decl.composite->mode.name, obj)));
    return;
  }
  const int slot = element_slot_[static_cast<std::size_t>(decl)];
  if (slot < 0) return; // the element itself has errors, already reported
  ElementSpec& e = net.elements[static_cast<std::size_t>(slot)];
  const KeySchema* ks = e.schema->key(key);
  if (!ks || ks->type == KeyType::node) {
    std::vector<std::string> names;
    for (const auto& k : e.schema->keys)
      if (k.type != KeyType::node) names.push_back(k.name);
    Diagnostic d = DiagnosticEngine::make(DiagId::unknown_key, at, key_span,
                                          fmt::format("element kind '{}'", e.kind), key);
    if (ks) // a node-valued key such as 'sense' is part of the wiring, not a value
      d.notes.push_back(DiagnosticEngine::note(
          DiagId::note_text, std::nullopt,
          fmt::format("'{}' names a node and cannot be set by a case", key)));
    else if (auto s = closest_match(key, names))
      d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
    else
      d.notes.push_back(
          DiagnosticEngine::note(DiagId::note_text, std::nullopt,
                                 fmt::format("'{}' takes: {}", e.kind, list_names(names))));
    report(std::move(d));
    return;
  }
  Place p{[&] { return fmt::format("{} of {} '{}'", key, e.kind, e.name); }, ks->dim,
          ks->absolute_temperature, ks};
  if (ks->type == KeyType::number && !boost::get<ast::Expr>(&a.value)) {
    report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, key_span, p.what()));
    return;
  }
  if (auto v = signal(a.value, f, p, at)) e.values[key] = std::move(*v);
}

void Elaborator::check_data(const NetworkSpec& net, const std::string& path, Span at, Span mark) {
  try {
    CsvTable t = read_csv(path);
    check_measured(t);
    data_times_ = DataTimes{CsvTable{path, {"time"}, {t.time()}}, at, mark};
    for (std::size_t c = 1; c < t.columns.size(); ++c) {
      if (net.node_index(t.columns[c]) >= 0 || m_.declared_by_unparsed(t.columns[c])) continue;
      Diagnostic d = DiagnosticEngine::make(DiagId::data_unknown_column, at, mark, t.columns[c]);
      d.message += fmt::format(" (in {}, column {})", fs::path(path).filename().string(), c + 1);
      std::vector<std::string> names;
      for (const auto& n : net.nodes)
        names.push_back(n.name);
      if (auto s = closest_match(t.columns[c], names))
        d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
      report(std::move(d));
    }
  } catch (const CsvError& e) {
    std::string msg = e.what();
    if (e.row == 0)
      report(DiagnosticEngine::make(DiagId::data_unreadable, at, mark, path,
                                    msg.substr(std::min(msg.size(), path.size() + 2))));
    else
      report(DiagnosticEngine::make(DiagId::data_format, at, mark, msg));
  }
}

} // namespace thermnet::lang
