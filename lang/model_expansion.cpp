// Expanding a loaded model's loops and submodel instances into one declaration per name,
// resolving the nodes elements connect, and reporting problems once per generated place.

#include "lang/model_builder.hpp"

#include "lang/elaborator.hpp"
#include "lang/keywords.hpp"
#include "lang/loop_iteration.hpp"
#include "lang/model.hpp"

#include <map>
#include <set>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

namespace thermnet::lang {

void ModelBuilder::finish() {
  std::vector<std::string_view> vars;
  for (const auto& sub : m_.submodels_)
    check_block(sub.stmt->body, sub.file, false, &sub, vars);
  find_submodel_cycles();
  for (const auto& [stmt, f] : structure_)
    if (const auto* loop = std::get_if<ast::ForStmt>(stmt)) check_loop(*loop, f, nullptr, vars);
  elaborator_.emplace(
      Elaborator::structural(m_, [this](Diagnostic d) { report(std::move(d), nullptr, true); }));
  // A flat model declares one name per statement: size the indices once (robin-hood hashing
  // stays fast well above the default load factor of 0.5, and a bucket costs 12 bytes).
  std::size_t nodes = 0, elements = 0;
  for (const auto& [stmt, f] : structure_) {
    nodes += std::holds_alternative<ast::NodeStmt>(*stmt);
    elements += std::holds_alternative<ast::ElementStmt>(*stmt) ||
                std::holds_alternative<ast::CompositeStmt>(*stmt);
  }
  m_.node_index_.reserve(nodes, 0.8f);
  m_.element_index_.reserve(elements, 0.8f);
  for (const auto& [stmt, f] : structure_) {
    if (stopped_ || diags_.saturated()) break;
    expand(*stmt, f, nullptr);
  }
  resolve();
  m_.truncated_ = stopped_;
  m_.structurally_used_ = elaborator_->used_names();
}

bool ModelBuilder::count(FileId f, const ast::Tagged& where) {
  if (!affordable(1, f, where)) return false;
  ++work_;
  return true;
}

bool ModelBuilder::affordable(std::size_t n, FileId f, const ast::Tagged& where) {
  if (stopped_) return false;
  if (n <= opt_.max_generated - work_) return true; // work_ never passes the limit
  stopped_ = true;
  Diagnostic d = DiagnosticEngine::make(DiagId::too_much_generated, at(f, where), span(f, where),
                                        opt_.max_generated);
  if (!opt_.too_large_note.empty())
    d.notes.push_back(DiagnosticEngine::note(DiagId::note_text, std::nullopt, opt_.too_large_note));
  report(std::move(d), nullptr, true);
  return false;
}

void ModelBuilder::expand(const ast::Statement& s, FileId f, const Scope* scope) {
  if (const auto* n = std::get_if<ast::NodeStmt>(&s)) {
    declare_nodes(*n, f, scope);
  } else if (const auto* e = std::get_if<ast::ElementStmt>(&s)) {
    if (const SubmodelDecl* sub = m_.submodel(e->kind.name))
      instantiate(*e, *sub, f, scope);
    else
      declare_elements(e, nullptr, f, scope);
  } else if (const auto* c = std::get_if<ast::CompositeStmt>(&s)) {
    declare_elements(nullptr, c, f, scope);
  } else if (const auto* loop = std::get_if<ast::ForStmt>(&s);
             loop && !bad_loops_.count(loop) &&
             !failed_loops_.count({loop, scope ? scope->instance() : nullptr})) {
    Scope partial = Scope::loop(scope, f, loop->begin, loop->ranges);
    iterate(*loop, partial);
  }
  // Anything else in a body was reported by check_block (or is a submodel's param or const).
}

void ModelBuilder::iterate(const ast::ForStmt& loop, Scope& partial) {
  const FileId f = partial.file;
  const auto bounds = [&](std::size_t k) -> std::optional<LoopBounds> {
    const ast::LoopRange& r = loop.ranges[k];
    try {
      const long lo = elaborator_->whole_number(r.lo, f, &partial, "the first value of a loop");
      const long hi = elaborator_->whole_number(r.hi, f, &partial, "the last value of a loop");
      // The whole range is counted before it runs: a huge one is refused at once.
      if (hi >= lo && !affordable(static_cast<std::size_t>(hi - lo) + 1, f, loop))
        return std::nullopt;
      return LoopBounds{lo, hi};
    } catch (const EvalError& e) {
      // Reported once: the loop runs no more, here or in the iterations of the loops around it
      // (a wrong bound inside 20 nested loops would otherwise be evaluated a million times).
      if (!e.diag.code.empty()) report(located(e.diag, f, loop), partial.parent, true);
      failed_loops_.emplace(&loop, partial.instance());
      return std::nullopt;
    }
  };
  const auto body = [&] {
    const std::size_t nodes = m_.nodes_.size(), elements = m_.elements_.size(),
                      scopes = m_.scopes_.size();
    const Scope& iteration = m_.scopes_.emplace_back(partial);
    for (const auto& s : loop.body) {
      if (stopped_) break;
      expand(s, f, &iteration);
    }
    // Nothing refers to the scope of an iteration that declared nothing: it is not kept.
    if (m_.nodes_.size() == nodes && m_.elements_.size() == elements &&
        m_.scopes_.size() == scopes + 1)
      m_.scopes_.pop_back();
    return !stopped_;
  };
  for_each_iteration(
      loop.ranges.size(), partial.values, bounds, [&] { return count(f, loop); }, body);
}

bool ModelBuilder::declared_names(const ast::Ref& name, FileId f, const Scope* scope,
                                  const ast::Tagged& stmt, std::vector<std::string>& out) {
  out.clear();
  const Scope* inst = scope ? scope->instance() : nullptr;
  std::string base = inst ? inst->prefix : std::string();
  base += name.id.name;
  if (name.plain()) {
    out.push_back(std::move(base));
    return true;
  }
  std::vector<std::pair<long, long>> ranges;
  try {
    for (const auto& item : name.index()) {
      const long lo = elaborator_->whole_number(item.lo, f, scope, "an index");
      const long hi = item.hi ? elaborator_->whole_number(*item.hi, f, scope, "an index") : lo;
      if (hi < lo) return true; // an empty range declares nothing
      ranges.emplace_back(lo, hi);
    }
  } catch (const EvalError& e) {
    if (!e.diag.code.empty()) report(located(e.diag, f, stmt), scope, true);
    return false;
  }
  // Every name is counted before one is made: a huge range is refused at once.
  std::size_t total = 1;
  for (const auto& r : ranges) {
    const auto n = static_cast<std::size_t>(r.second - r.first) + 1;
    total = total > opt_.max_generated / n ? opt_.max_generated + 1 : total * n;
  }
  if (!affordable(total, f, stmt)) return false;
  std::vector<long> at_index;
  for (const auto& r : ranges)
    at_index.push_back(r.first);
  for (;;) {
    if (!count(f, stmt)) return false;
    std::string n = base + '[';
    for (std::size_t i = 0; i < at_index.size(); ++i) {
      if (i) n += ',';
      n += std::to_string(at_index[i]);
    }
    out.push_back(n + ']');
    std::size_t i = at_index.size();
    while (i-- > 0) {
      if (at_index[i] < ranges[i].second) {
        ++at_index[i];
        break;
      }
      at_index[i] = ranges[i].first;
    }
    if (i == static_cast<std::size_t>(-1)) return true;
  }
}

void ModelBuilder::declare_nodes(const ast::NodeStmt& s, FileId f, const Scope* scope) {
  if (!declared_names(s.name, f, scope, s, names_)) return;
  const char* what = s.boundary ? "boundary" : "node";
  for (std::string& name : names_) {
    NodeDecl& d = m_.nodes_.emplace_back();
    d.stmt = &s;
    d.name = kept_name(s.name, scope, name);
    d.scope = scope;
    d.file = f;
    d.boundary = s.boundary;
    const int index = static_cast<int>(m_.nodes_.size() - 1);
    const int first = m_.node_index_.insert(index);
    std::optional<Span> previous;
    if (first >= 0) previous = m_.nodes_[static_cast<std::size_t>(first)].name_span();
    check_name(what, s.name.id.name, d.name, d.name_span(), at(f, s),
               previous ? &*previous : nullptr, scope);
    if (first >= 0) m_.nodes_.pop_back();
  }
}

std::string_view ModelBuilder::kept_name(const ast::Ref& ref, const Scope* scope,
                                         std::string_view name) {
  if (ref.plain() && !(scope && scope->instance())) return ref.id.name;
  return m_.name_text_.keep(name);
}

bool ModelBuilder::element_name(std::string_view name, int index, const Scope* instance,
                                std::string_view base, Span name_span, Span where,
                                const Scope* scope) {
  // One hash lookup for the common case, a new element's name: it is entered at once and taken
  // out again if an instance has it.
  std::optional<Span> previous;
  bool entered = false;
  if (instance) {
    if (const int i = m_.element_index_.find(name); i >= 0)
      previous = m_.elements_[static_cast<std::size_t>(i)].name_span();
  } else if (const int i = m_.element_index_.insert(index); i >= 0) {
    previous = m_.elements_[static_cast<std::size_t>(i)].name_span();
  } else {
    entered = true;
  }
  if (!previous && !m_.instance_index_.empty())
    if (const Scope* other = m_.instance(name))
      previous = span(other->file, other->statement->name);
  check_name(instance ? "instance" : "element", base, name, name_span, where,
             previous ? &*previous : nullptr, scope);
  if (previous) {
    if (entered) m_.element_index_.erase(name);
    return false;
  }
  if (instance) m_.instance_index_.emplace(name, instance);
  return true;
}

void ModelBuilder::declare_elements(const ast::ElementStmt* e, const ast::CompositeStmt* c,
                                    FileId f, const Scope* scope) {
  const ast::Tagged& s = e ? static_cast<const ast::Tagged&>(*e) : *c;
  const ast::Ref& name = e ? e->name : c->name;
  const ElementSchema* schema = nullptr;
  bool valid = true;
  if (e) {
    schema = kind_schema(e->kind.name);
    if (!schema) {
      Diagnostic d =
          DiagnosticEngine::make(DiagId::unknown_kind, at(f, s), span(f, e->kind), e->kind.name);
      std::vector<std::string> kinds = m_.catalog().kinds();
      for (const auto& sub : m_.submodels_)
        kinds.push_back(sub.name);
      if (auto k = closest_match(std::string(e->kind.name), kinds))
        d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *k));
      report(std::move(d), scope, true);
      valid = false;
    } else if (e->mean && !schema->observes) {
      report(DiagnosticEngine::make(
                 DiagId::wrong_terminals_text, at(f, s),
                 Span{f, e->nodes.front().begin, e->nodes.back().end},
                 fmt::format("only a sensor reads the mean of several nodes (sensor s mean(a, "
                             "b)); element kind '{}' takes {} terminal node(s)",
                             e->kind.name, schema->terminals)),
             scope, true);
      valid = false;
    } else if (!e->mean && static_cast<int>(e->nodes.size()) != schema->terminals) {
      Span mark = e->nodes.empty() ? span(f, e->name)
                                   : Span{f, e->nodes.front().begin, e->nodes.back().end};
      report(DiagnosticEngine::make(DiagId::wrong_terminals, at(f, s), mark, e->kind.name,
                                    schema->terminals, e->nodes.size()),
             scope, true);
      valid = false;
    }
  }
  if (!declared_names(name, f, scope, s, names_)) return;
  for (std::string& n : names_) {
    const int index = static_cast<int>(m_.elements_.size());
    ElementDecl& d = m_.elements_.emplace_back();
    d.element = e;
    d.composite = c;
    d.name = kept_name(name, scope, n);
    d.scope = scope;
    d.schema = schema;
    d.file = f;
    d.valid = valid;
    if (!element_name(d.name, index, nullptr, name.id.name, span(f, name), at(f, s), scope))
      m_.elements_.pop_back();
  }
}

const ElementSchema* ModelBuilder::kind_schema(std::string_view kind) {
  if (last_schema_ && kind == last_kind_) return last_schema_;
  const ElementSchema* schema = m_.catalog().find(kind);
  if (schema) {
    last_kind_ = kind;
    last_schema_ = schema;
  }
  return schema;
}

void ModelBuilder::check_arguments(const ast::ElementStmt& s, const SubmodelDecl& sub, FileId f,
                                   const Scope* scope, const std::string& name) {
  if (s.mean) {
    report(DiagnosticEngine::make(
               DiagId::wrong_terminals_text, at(f, s),
               Span{f, s.nodes.front().begin, s.nodes.back().end},
               fmt::format("only a sensor reads the mean of several nodes; submodel '{}' takes "
                           "its {} terminal node(s) as a list",
                           sub.name, sub.stmt->terminals.size())),
           scope, true);
    return;
  }
  if (s.nodes.size() != sub.stmt->terminals.size()) {
    Span mark =
        s.nodes.empty() ? span(f, s.name) : Span{f, s.nodes.front().begin, s.nodes.back().end};
    report(DiagnosticEngine::make(DiagId::instance_terminals, at(f, s), mark, sub.name,
                                  sub.stmt->terminals.size(), s.nodes.size()),
           scope, true);
  }
  std::vector<std::string> params;
  for (const auto& v : sub.values)
    if (v.is_param) params.push_back(v.name);
  std::set<std::string_view> given;
  for (const auto& kv : s.keys) {
    const int k = sub.value_index(kv.key.name);
    if (k < 0 || !sub.values[static_cast<std::size_t>(k)].is_param) {
      Diagnostic d = DiagnosticEngine::make(DiagId::unknown_key, at(f, s), span(f, kv.key),
                                            fmt::format("submodel '{}'", sub.name), kv.key.name);
      d.message = fmt::format("submodel '{}' has no param '{}'", sub.name, kv.key.name);
      if (auto m = closest_match(std::string(kv.key.name), params))
        d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *m));
      else
        d.notes.push_back(DiagnosticEngine::note(
            DiagId::note_text, std::nullopt,
            params.empty() ? fmt::format("submodel '{}' has no params", sub.name)
                           : fmt::format("its params: {}", fmt::join(params, ", "))));
      report(std::move(d), scope, true);
    } else if (!given.insert(kv.key.name).second) {
      report(DiagnosticEngine::make(DiagId::duplicate_key, at(f, s), span(f, kv.key), kv.key.name),
             scope, true);
    }
  }
  for (const auto& v : sub.values)
    if (v.is_param && !v.expr && !given.count(v.name))
      report(DiagnosticEngine::make(DiagId::missing_argument, at(f, s), span(f, s.name), name,
                                    sub.name, v.name),
             scope, true);
}

void ModelBuilder::instantiate(const ast::ElementStmt& s, const SubmodelDecl& sub, FileId f,
                               const Scope* scope) {
  if (!declared_names(s.name, f, scope, s, names_)) return;
  std::vector<std::string> names = std::move(names_);
  for (std::string& name : names) {
    if (stopped_) return;
    Scope& inst = m_.scopes_.emplace_back();
    inst.prefix = name + '.';
    inst.name = std::move(name);
    inst.file = f;
    inst.statement = &s;
    // The instance's name is registered as a view of the scope's own copy, which stays put.
    if (!element_name(inst.name, -1, &inst, s.name.id.name, span(f, s.name), at(f, s), scope)) {
      m_.scopes_.pop_back();
      continue;
    }
    check_arguments(s, sub, f, scope, inst.name);
    inst.kind = Scope::Kind::instance;
    inst.parent = scope;
    inst.where = span(f, s);
    inst.submodel = &sub;
    inst.terminals.assign(sub.stmt->terminals.size(), -1);
    inst.slot = m_.instance_slots_;
    m_.instance_slots_ += sub.values.size();
    if (cyclic_.count(&sub)) continue; // reported at its definition; its body is not expanded
    if (depth_ >= max_instance_depth) {
      report(DiagnosticEngine::make(DiagId::submodel_too_deep, at(f, s), span(f, s.kind), inst.name,
                                    sub.name, max_instance_depth),
             nullptr, true);
      continue;
    }
    ++depth_;
    for (const auto& stmt : sub.stmt->body) {
      if (stopped_) break;
      expand(stmt, sub.file, &inst);
    }
    --depth_;
  }
}

void ModelBuilder::resolve() {
  for (Scope& s : m_.scopes_) {
    if (s.kind != Scope::Kind::instance) continue;
    const auto& refs = s.statement->nodes;
    for (std::size_t k = 0; k < refs.size() && k < s.terminals.size(); ++k)
      if (auto n = elaborator_->resolve_node(refs[k], s.file, s.parent,
                                             Span{s.file, s.where.begin, s.where.begin}))
        s.terminals[k] = *n;
  }
  const auto refs_of = [](const ElementDecl& d) -> const auto& {
    return d.element ? d.element->nodes : d.composite->nodes;
  };
  std::size_t count = 0;
  for (const ElementDecl& d : m_.elements_)
    count += refs_of(d).size();
  auto& terminals = m_.terminals_;
  terminals.reserve(count); // exactly: the declarations' spans view this array
  for (ElementDecl& d : m_.elements_) {
    const std::size_t first = terminals.size();
    const auto& refs = refs_of(d);
    if (!d.valid) { // its error is reported; its links still count for the topology warnings
      for (const auto& r : refs)
        terminals.push_back(elaborator_->find_node(r, d.file, d.scope));
    } else {
      const Span start{d.file, d.where().begin, d.where().begin};
      for (const auto& r : refs) {
        // A plain name at the top level is looked up directly (the common case of big files).
        int n = d.scope || !r.plain() ? -1 : m_.node_index(r.id.name);
        if (n < 0) n = elaborator_->resolve_node(r, d.file, d.scope, start).value_or(-1);
        terminals.push_back(n);
      }
    }
    d.nodes = std::span<const int>(terminals.data() + first, refs.size());
  }
}

Diagnostic ModelBuilder::located(Diagnostic d, FileId f, const ast::Tagged& stmt) {
  if (!d.mark) d.mark = d.at;
  d.at = at(f, stmt);
  return d;
}

void ModelBuilder::report(Diagnostic d, const Scope* scope, bool structural) {
  // (a repetition is dropped before its notes are made: a loop's millions of iterations)
  if (!reported_.first(d, scope)) return;
  add_scope_notes(d, scope);
  if (structural && d.severity == Severity::error && !m_.load_error_) m_.load_error_ = d;
  diags_.add(std::move(d));
}

} // namespace thermnet::lang
