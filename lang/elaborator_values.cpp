// The elaborator's values: params and consts, their expressions and the reads between them,
// references to nodes, numbers placed in their units and ranges, and the command line's param
// overrides.

#include "lang/elaborator.hpp"
#include "lang/elaborator_detail.hpp"

#include <boost/container/small_vector.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_set>
#include <utility>

namespace thermnet::lang {
using namespace detail;

std::vector<std::string> detail::compared_numbers(std::initializer_list<double> values,
                                                  std::string_view unit) {
  std::vector<std::string> out;
  for (double v : values)
    out.push_back(fmt::format("{:g}", v));
  bool alike = false;
  for (std::size_t i = 0; i < out.size(); ++i)
    for (std::size_t j = i + 1; j < out.size(); ++j)
      alike = alike || (out[i] == out[j] && values.begin()[i] != values.begin()[j]);
  if (alike) {
    out.clear();
    for (double v : values)
      out.push_back(fmt::format("{}", v));
  }
  for (std::string& x : out)
    x += unit;
  return out;
}

void detail::add_reads(ParamReads& into, const ParamReads& reads) {
  for (const ValueDecl* d : reads)
    if (std::find(into.begin(), into.end(), d) == into.end()) into.push_back(d);
}

void Elaborator::note_reads(const ParamReads& reads) {
  for (ParamReads* r : readers_)
    add_reads(*r, reads);
}

Evaluator Elaborator::evaluator(FileId f, const Scope* scope) {
  return Evaluator(
      m_.file(f),
      [this, scope](const ast::Identifier& id, FileId file) { return lookup(id, file, scope); },
      [this, scope](ast::Index node, FileId file) { return embedded_signal(node, file, scope); });
}

// Loop variables first (up to the instance), then the instance's params and consts, then the
// model's; `time` is the simulation time where a time signal may stand, unless a name hides it.
Quantity Elaborator::lookup(const ast::Identifier& id, FileId f, const Scope* scope) {
  for (const Scope* s = scope; s; s = s->parent) {
    if (s->kind == Scope::Kind::loop) {
      for (std::size_t k = 0; k < s->values.size(); ++k)
        if ((*s->ranges)[k].var.name == id.name)
          return Quantity{static_cast<double>(s->values[k]), std::nullopt};
      continue;
    }
    if (const int k = s->submodel->value_index(id.name); k >= 0)
      return instance_value(*s, k, span_of(f, id));
    break; // an instance's body sees nothing of the scopes around the instance
  }
  if (id.name == "time" && !value_decls_.count("time")) {
    if (!time_allowed_)
      throw EvalError(
          DiagnosticEngine::make(DiagId::time_not_allowed, span_of(f, id), span_of(f, id)));
    saw_time_ = true;
    return Quantity{0.0, std::nullopt};
  }
  used_.emplace(id.name);
  return value_of(id.name, span_of(f, id));
}

Quantity Elaborator::value_of(std::string_view name, Span use) {
  auto decl_it = value_decls_.find(name);
  if (decl_it == value_decls_.end()) {
    if (m_.declared_by_unparsed(name)) throw EvalError(Diagnostic{}); // its syntax error is out
    Diagnostic d = DiagnosticEngine::make(DiagId::unknown_name, use, use, name);
    suggest(d, std::string(name), [&] {
      std::vector<std::string> names;
      for (const auto& v : m_.values())
        names.push_back(v.name);
      return names;
    });
    throw EvalError(std::move(d));
  }
  const ValueDecl& decl = *decl_it->second;
  if (structural_ && decl.is_param)
    throw EvalError(DiagnosticEngine::make(DiagId::structure_param, use, use, name));
  if (auto it = values_.find(decl.name); it != values_.end()) {
    if (std::isnan(it->second.value)) throw EvalError(Diagnostic{}); // failed earlier, reported
    if (recording_) note_reads(value_reads_[&decl]);
    return it->second;
  }
  // A declaration's problems are its own: no loop or instance of the use, no `time`.
  Restore<const Scope*> no_context(context_, nullptr);
  Restore<bool> no_time(time_allowed_, false);
  Span at{decl.file, decl.where.begin, decl.where.begin};
  for (std::size_t i = 0; i < evaluating_.size(); ++i)
    if (evaluating_[i] == decl.name) {
      std::string path;
      for (std::size_t k = i; k < evaluating_.size(); ++k)
        path += evaluating_[k] + " -> ";
      throw EvalError(
          DiagnosticEngine::make(DiagId::cycle, at, decl.name_span, decl.name, path + decl.name));
    }
  evaluate_reads_first(decl);
  if (auto it = values_.find(decl.name); it != values_.end()) { // a cycle through it, reported
    if (std::isnan(it->second.value)) throw EvalError(Diagnostic{});
  }
  evaluating_.push_back(decl.name);
  ParamReads reads; // a param reads itself, and what its expression and range read
  if (decl.is_param) reads.push_back(&decl);
  Reading reading(*this, reads);
  Quantity q;
  try {
    q = evaluator(decl.file, nullptr).eval(*decl.expr);
  } catch (const EvalError& e) {
    evaluating_.pop_back();
    values_[decl.name] = Quantity{std::nan(""), std::nullopt};
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
      Evaluator ev = evaluator(decl.file, nullptr);
      Quantity lo = ev.eval(decl.range->lo), hi = ev.eval(decl.range->hi);
      for (const Quantity* b : {&lo, &hi})
        if (b->dim && q.dim && !(*b->dim == *q.dim))
          report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_of(decl.file, *decl.range),
                                        fmt::format("the range of param '{}'", decl.name),
                                        describe(*q.dim), describe(*b->dim)));
      if (!q.dim && lo.dim && hi.dim && !(*lo.dim == *hi.dim)) // (else checked against q above)
        report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_of(decl.file, *decl.range),
                                      fmt::format("the upper bound of param '{}'", decl.name),
                                      describe(*lo.dim), describe(*hi.dim)));
      // A bare value takes the unit its range gives (temperatures excepted: bare ones are degC).
      if (const auto& b = lo.dim ? lo.dim : hi.dim; !q.dim && b && !(*b == dim::temperature))
        q.dim = b;
      const auto shown = compared_numbers({q.value, lo.value, hi.value});
      if (!(lo.value < hi.value))
        report(DiagnosticEngine::make(DiagId::bad_range, at, span_of(decl.file, *decl.range),
                                      decl.name, shown[1], shown[2]));
      else if (q.value < lo.value || q.value > hi.value)
        report(DiagnosticEngine::make(DiagId::param_outside_range, at,
                                      span_of(decl.file, *decl.expr), decl.name, shown[0], shown[1],
                                      shown[2]));
      ranges_[decl.name] = {lo.value, hi.value};
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
  if (auto o = overrides_.find(decl.name); o != overrides_.end()) q.value = o->second;
  values_[decl.name] = q;
  reading.stop();
  if (recording_) {
    if (auto c = case_reads_.find(&decl); c != case_reads_.end()) add_reads(reads, c->second);
    note_reads(reads);
    value_reads_[&decl] = std::move(reads);
  }
  return q;
}

namespace {

/// The names an expression reads (consts, params and builtins alike), in the order written.
void names_read(const ast::File& file, const ast::Expr& e, std::vector<std::string_view>& out) {
  if (!e.valid()) return;
  std::vector<ast::Index> stack{e.root};
  while (!stack.empty()) {
    const ast::ExprNode& n = file.node(stack.back());
    stack.pop_back();
    switch (n.op) {
    case ast::ExprNode::Op::name:
      out.push_back(file.names[n.a].name);
      break;
    case ast::ExprNode::Op::negate:
    case ast::ExprNode::Op::group:
      stack.push_back(n.a);
      break;
    case ast::ExprNode::Op::add:
    case ast::ExprNode::Op::subtract:
    case ast::ExprNode::Op::multiply:
    case ast::ExprNode::Op::divide:
    case ast::ExprNode::Op::power:
      stack.push_back(n.b); // (popped after a: left to right)
      stack.push_back(n.a);
      break;
    case ast::ExprNode::Op::call: {
      const auto args = file.call_args(n);
      for (auto it = args.rbegin(); it != args.rend(); ++it)
        stack.push_back(*it);
      break;
    }
    default:
      break;
    }
  }
}

} // namespace

// A value's expression is evaluated by recursion into the values it reads: a chain of 100,000
// consts (c1 = c0 + 1, c2 = c1 + 1, ...) would recurse 100,000 deep and overflow the stack. The
// values `decl` reads, and theirs, are therefore found first (depth-first, with a stack of its
// own) and evaluated deepest first, each then finding what it reads already evaluated. A cycle
// among them is reported here, as value_of() would report it, and its members fail.
void Elaborator::evaluate_reads_first(const ValueDecl& decl) {
  if (reads_first_) return;
  Restore<bool> busy(reads_first_, true);
  const auto pending = [&](std::string_view name) -> const ValueDecl* {
    if (name == "time" || values_.count(name)) return nullptr;
    auto it = value_decls_.find(name);
    if (it == value_decls_.end()) return nullptr;
    if (structural_ && it->second->is_param) return nullptr; // reported at its use
    if (std::find(evaluating_.begin(), evaluating_.end(), name) != evaluating_.end())
      return nullptr; // a cycle through a value under way: value_of() reports it
    return it->second;
  };
  struct Frame {
    const ValueDecl* decl;
    std::vector<std::string_view> reads; // its expression's, then its range's
    std::size_t in_expression = 0;       // how many of them its expression reads
    std::size_t next = 0;
  };
  const auto frame_of = [&](const ValueDecl& d) {
    Frame f{&d, {}};
    const ast::File& file = m_.file(d.file);
    if (d.expr) names_read(file, *d.expr, f.reads);
    f.in_expression = f.reads.size();
    if (d.is_param && d.range) {
      names_read(file, d.range->lo, f.reads);
      names_read(file, d.range->hi, f.reads);
    }
    return f;
  };
  std::vector<Frame> stack;
  std::unordered_map<const ValueDecl*, bool> seen; // true while on the stack
  std::vector<const ValueDecl*> order;             // deepest first
  std::unordered_set<const ValueDecl*> in_range_cycle;
  stack.push_back(frame_of(decl));
  seen[&decl] = true;
  while (!stack.empty()) {
    Frame& top = stack.back();
    if (top.next == top.reads.size()) {
      seen[top.decl] = false;
      if (top.decl != &decl) order.push_back(top.decl);
      stack.pop_back();
      continue;
    }
    const bool in_range = top.next >= top.in_expression;
    const ValueDecl* d = pending(top.reads[top.next++]);
    if (!d) continue;
    if (auto it = seen.find(d); it != seen.end()) {
      if (!it->second) continue; // found before
      const auto from =
          std::find_if(stack.begin(), stack.end(), [&](const Frame& f) { return f.decl == d; });
      // A cycle through a param's range (`param p = 1 range 0 .. p`) keeps the param's value:
      // value_of() reports it, as it evaluates the range after the value.
      const bool through_range = in_range || std::any_of(from, stack.end() - 1, [](const Frame& f) {
                                   return f.next - 1 >= f.in_expression;
                                 });
      if (through_range) { // and its values are left to be evaluated in the order written
        for (auto f = from; f != stack.end(); ++f)
          in_range_cycle.insert(f->decl);
        continue;
      }
      // A cycle of values: d is on the stack. It is reported at d, as evaluating d reports it,
      // and every value on it fails (each is read by the one before: none is unused).
      std::string path;
      for (auto f = from; f != stack.end(); ++f) {
        path += f->decl->name + " -> ";
        values_[f->decl->name] = Quantity{std::nan(""), std::nullopt};
        used_.emplace(f->decl->name);
      }
      report(DiagnosticEngine::make(DiagId::cycle, Span{d->file, d->where.begin, d->where.begin},
                                    d->name_span, d->name, path + d->name));
      continue;
    }
    seen[d] = true;
    stack.push_back(frame_of(*d));
  }
  for (const ValueDecl* d : order) {
    if (values_.count(d->name) || in_range_cycle.count(d)) continue;
    try {
      value_of(d->name, d->name_span);
    } catch (const EvalError&) { // reported (or to be reported where it is used)
    }
  }
}

// An instance's param is the value its statement gives (evaluated where the statement stands),
// else its default; a const is evaluated inside the instance. Each is evaluated once per run.
Quantity Elaborator::instance_value(const Scope& inst, int index, Span use) {
  const std::size_t slot = inst.slot + static_cast<std::size_t>(index);
  if (slot >= instance_values_.size()) instance_values_.resize(slot + 1);
  if (recording_ && slot >= instance_reads_.size()) instance_reads_.resize(slot + 1);
  if (const auto& cached = instance_values_[slot]) {
    if (std::isnan(cached->value)) throw EvalError(Diagnostic{}); // failed earlier, reported
    if (recording_) note_reads(instance_reads_[slot]);
    return *cached;
  }
  const ValueDecl& decl = inst.submodel->values[static_cast<std::size_t>(index)];
  const std::string full = inst.prefix + decl.name;
  for (std::size_t i = 0; i < evaluating_.size(); ++i)
    if (evaluating_[i] == full) {
      std::string path;
      for (std::size_t k = i; k < evaluating_.size(); ++k)
        path += evaluating_[k] + " -> ";
      throw EvalError(DiagnosticEngine::make(DiagId::cycle, use, use, full, path + full));
    }
  const ast::KeyValue* arg = nullptr;
  if (decl.is_param)
    for (const auto& kv : inst.statement->keys)
      if (kv.key.name == decl.name) arg = &kv;
  if (!arg && !decl.expr) { // a required param the instance does not give: reported at load
    instance_values_[slot] = Quantity{std::nan(""), std::nullopt};
    throw EvalError(Diagnostic{});
  }
  Restore<bool> no_time(time_allowed_, false);
  evaluating_.push_back(full);
  ParamReads reads;
  Reading reading(*this, reads);
  Quantity q;
  try {
    if (arg) {
      Restore<const Scope*> outer(context_, inst.parent);
      const ast::Expr* e = arg->value.as_expr();
      if (!e)
        throw EvalError(DiagnosticEngine::make(
            DiagId::signal_not_allowed, Span{inst.file, inst.where.begin, inst.where.begin},
            span_of(inst.file, arg->value.span()),
            fmt::format("param '{}' of an instance", decl.name)));
      q = evaluator(inst.file, inst.parent).eval(*e);
    } else {
      Restore<const Scope*> inside(context_, &inst);
      q = evaluator(decl.file, &inst).eval(*decl.expr);
    }
  } catch (const EvalError& e) {
    evaluating_.pop_back();
    instance_values_[slot] = Quantity{std::nan(""), std::nullopt};
    if (e.diag.code.empty()) throw;
    Diagnostic d = e.diag;
    const Span at = arg ? Span{inst.file, inst.where.begin, inst.where.begin}
                        : Span{decl.file, decl.where.begin, decl.where.begin};
    d.at = at;
    Restore<const Scope*> where(context_, arg ? inst.parent : &inst);
    report(std::move(d));
    throw EvalError(Diagnostic{});
  }
  evaluating_.pop_back();
  instance_values_[slot] = q;
  reading.stop();
  if (recording_) {
    note_reads(reads);
    instance_reads_[slot] = std::move(reads);
  }
  return q;
}

Quantity Elaborator::evaluate(const ast::Expr& e, FileId file, const Scope* scope) {
  Restore<const Scope*> context(context_, scope);
  return evaluator(file, scope).eval(e);
}

long Elaborator::whole_number(const ast::Expr& e, FileId file, const Scope* scope,
                              const char* what) {
  const Quantity q = evaluate(e, file, scope);
  const Span s = span_of(file, e);
  if (q.dim && !q.dim->dimensionless())
    throw EvalError(DiagnosticEngine::make(
        DiagId::bad_index, s, s,
        fmt::format("{} must be a whole number, not a quantity of dimension {}", what,
                    describe(*q.dim))));
  if (q.value != std::round(q.value))
    throw EvalError(
        DiagnosticEngine::make(DiagId::bad_index, s, s,
                               fmt::format("{} must be a whole number, got {:g}", what, q.value)));
  if (std::abs(q.value) > 1e15)
    throw EvalError(DiagnosticEngine::make(
        DiagId::bad_index, s, s,
        fmt::format("{} must lie between -1e15 and 1e15, got {:g}", what, q.value)));
  return static_cast<long>(q.value);
}

std::string Elaborator::reference_text(const ast::Ref& r, FileId file, const Scope* scope) {
  std::string out(r.id.name);
  auto index = [&](const std::vector<ast::IndexItem>& items) {
    if (items.empty()) return;
    out += '[';
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (items[i].hi)
        throw EvalError(DiagnosticEngine::make(
            DiagId::bad_index, span_of(file, items[i]), span_of(file, items[i]),
            "a range 'LO .. HI' may stand only in the name a statement declares"));
      if (i) out += ',';
      out += std::to_string(whole_number(items[i].lo, file, scope, "an index"));
    }
    out += ']';
  };
  index(r.index());
  for (const auto& part : r.rest()) {
    out += '.';
    out += part.id.name;
    index(part.index());
  }
  return out;
}

int Elaborator::find_node(const ast::Ref& r, FileId file, const Scope* scope) {
  const Scope* inst = scope ? scope->instance() : nullptr;
  if (inst && r.plain())
    if (const int k = inst->submodel->terminal_index(r.id.name); k >= 0)
      return inst->terminals[static_cast<std::size_t>(k)];
  try {
    const std::string text = reference_text(r, file, scope);
    return m_.node_index(inst ? inst->prefix + text : text);
  } catch (const EvalError&) {
    return -1;
  }
}

std::optional<int> Elaborator::resolve_node(const ast::Ref& r, FileId file, const Scope* scope,
                                            Span at) {
  Restore<const Scope*> context(context_, scope);
  std::string text;
  try {
    text = reference_text(r, file, scope);
  } catch (const EvalError& e) {
    if (!e.diag.code.empty()) {
      Diagnostic d = e.diag;
      d.at = at;
      report(std::move(d));
    }
    return std::nullopt;
  }
  const Scope* inst = scope ? scope->instance() : nullptr;
  if (inst && r.plain())
    if (const int k = inst->submodel->terminal_index(r.id.name); k >= 0) {
      const int n = inst->terminals[static_cast<std::size_t>(k)];
      return n >= 0 ? std::optional<int>(n) : std::nullopt; // (reported at the instance)
    }
  const std::string full = inst ? inst->prefix + text : text;
  if (const int i = m_.node_index(full); i >= 0) return i;
  if (m_.declared_by_unparsed(r.id.name)) return std::nullopt; // its syntax error is reported
  Diagnostic d = DiagnosticEngine::make(DiagId::unknown_node, at, span_of(file, r), text);
  // Suggest a name the reference could have meant: among the instance's own nodes and terminals
  // inside a submodel, else among the model's.
  const bool suggested = suggest(d, text, [&] {
    std::vector<std::string> names;
    if (inst)
      for (const auto& t : inst->submodel->stmt->terminals)
        names.emplace_back(t.name);
    for (const auto& n : m_.nodes())
      if (!inst)
        names.emplace_back(n.name);
      else if (n.name.starts_with(inst->prefix))
        names.emplace_back(n.name.substr(inst->prefix.size()));
    return names;
  });
  if (!suggested && inst) {
    std::vector<std::string> terminals;
    for (const auto& t : inst->submodel->stmt->terminals)
      terminals.emplace_back(t.name);
    d.notes.push_back(DiagnosticEngine::note(
        DiagId::note_text, std::nullopt,
        fmt::format("inside submodel '{}', a node is one of its own or a terminal ({})",
                    inst->submodel->name, list_names(terminals))));
  }
  report(std::move(d));
  return std::nullopt;
}

std::optional<double> Elaborator::to_place(const Quantity& q, const Place& p, Span at, Span mark) {
  if (q.dim && !(*q.dim == p.dim)) {
    report(DiagnosticEngine::make(DiagId::unit_mismatch, at, mark, p.what(), describe(p.dim),
                                  describe(*q.dim)));
    return std::nullopt;
  }
  // A temperature difference drops what degC/degF added (0.4 [degC] is 0.4 K).
  const double v = p.key && p.key->temperature_difference
                       ? q.value - q.zero
                       : q.value + bare_temperature_offset(q, p.absolute_temperature);
  if (!check_range(v, p, at, mark)) return std::nullopt;
  return v;
}

bool Elaborator::check_range(double v, const Place& p, Span at, Span mark) {
  if (!p.key || p.key->accepts(v)) return true;
  std::string range =
      p.key->absolute_temperature ? "above absolute zero (-273.15 degC)" : p.key->range_text();
  report(DiagnosticEngine::make(DiagId::out_of_range, at, mark, p.what(), range,
                                format_outside(v, *p.key, p.dim, p.absolute_temperature)));
  return false;
}

void Elaborator::report_at(const EvalError& err, Span at) {
  if (err.diag.code.empty()) return; // already reported where it arose
  Diagnostic d = err.diag;
  d.at = at;
  report(std::move(d));
}

std::optional<double> Elaborator::number(const ast::Expr& e, FileId f, const Place& p, Span at) {
  try {
    Restore<bool> time(time_allowed_, false);
    Restore<const Place*> place(constant_place_, &p);
    return to_place(evaluator(f, context_).eval(e), p, at, span_of(f, e));
  } catch (const EvalError& err) {
    report_at(err, at);
    return std::nullopt;
  }
}

void Elaborator::apply_param_overrides() {
  std::set<std::string_view> seen;
  for (const auto& item : case_->stmt->items) {
    const auto* a = std::get_if<ast::CaseAssign>(&item);
    if (!a || !a->target.path.plain()) continue;
    const std::string_view name = a->target.path.id.name;
    if (is_case_key(name)) continue;
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
      if (auto s = closest_match(std::string(name), names))
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
    const ast::Expr* e = a->value.as_expr();
    if (!a->more.empty()) {
      report(DiagnosticEngine::make(DiagId::list_not_allowed, at,
                                    span_of(case_->file, a->more.front()),
                                    fmt::format("param '{}'", name)));
      continue;
    }
    if (!e) {
      report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, mark,
                                    fmt::format("param '{}'", name)));
      continue;
    }
    try {
      // (what the setting reads is what the param then reads: value_of())
      ParamReads& reads = case_reads_[&decl];
      Reading reading(*this, reads);
      Quantity declared = value_of(name, mark);
      Quantity q = evaluator(case_->file, nullptr).eval(*e);
      if (q.dim && declared.dim && !(*q.dim == *declared.dim)) {
        report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_of(case_->file, *e),
                                      fmt::format("param '{}'", name), describe(*declared.dim),
                                      describe(*q.dim)));
        continue;
      }
      pending_params_[decl.name] = q.value;
    } catch (const EvalError& err) {
      report_at(err, at);
    }
  }
  for (const auto& [k, v] : pending_params_)
    if (!external_->params.count(k)) overrides_[k] = v; // set from outside: kept
  values_.clear(); // values computed so far may have used the declared params
  std::fill(instance_values_.begin(), instance_values_.end(), std::nullopt);
  value_reads_.clear();
  instance_reads_.clear();
}

} // namespace thermnet::lang
