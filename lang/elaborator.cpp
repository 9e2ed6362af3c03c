#include "lang/elaborator.hpp"
#include "lang/elaborator_detail.hpp"

#include "lang/csv.hpp"
#include "lang/loop_iteration.hpp"
#include "lang/time_program.hpp"
#include "lang/units.hpp"

#include <boost/container/small_vector.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unordered_set>
#include <utility>

namespace thermnet::lang {
using namespace detail;
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

} // namespace

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

Elaborator::Elaborator(const Model& model, Reporter report, const CaseDecl* c,
                       const ParamValues& overrides, bool check_data, const Overrides* external)
    : m_(model), report_(std::move(report)), case_(c),
      external_(external ? external : &model.overrides()), check_data_(check_data) {
  overrides_ = external_->params;
  for (const auto& [name, value] : overrides)
    overrides_.insert_or_assign(name, value);
  for (const auto& v : m_.values())
    value_decls_.emplace(v.name, &v);
  instance_values_.resize(m_.instance_slots());
}

Elaborator Elaborator::structural(const Model& model, Reporter report) {
  Elaborator e(model, std::move(report), nullptr, {}, false);
  e.structural_ = true;
  return e;
}

void Elaborator::report(Diagnostic d) {
  // A problem inside a loop arises in every iteration (a million in a case's nested loops), and
  // the receivers keep the first per place: the repetitions are dropped before their notes.
  if (!generated_.first(d, context_)) return;
  add_scope_notes(d, context_);
  report_(std::move(d));
}

bool Elaborator::suggest(Diagnostic& d, const std::string& word,
                         const std::function<std::vector<std::string>()>& names) const {
  if (generated_.seen(d, context_)) return true;
  const std::optional<std::string> s = closest_match(word, names());
  if (s) d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
  return s.has_value();
}

// While it lives, every param read (directly or through a value) is noted in `into` too.
class Elaborator::Reading {
public:
  Reading(Elaborator& e, ParamReads& into) : e_(e), on_(e.recording_) {
    if (on_) e_.readers_.push_back(&into);
  }
  ~Reading() { stop(); }
  Reading(const Reading&) = delete;
  Reading& operator=(const Reading&) = delete;
  /// Ends the reading before the end of its scope.
  void stop() {
    if (on_) e_.readers_.pop_back();
    on_ = false;
  }

private:
  Elaborator& e_;
  bool on_;
};

namespace {

/// Numbers for a message that compares them (a value and its range's bounds): {:g} each, unless
/// that makes two different ones look equal (1.0000001 outside 0 .. 1 is not "1"); then all with
/// the digits that read back exactly. `unit` follows each (" degC", or empty).
std::vector<std::string> compared_numbers(std::initializer_list<double> values,
                                          std::string_view unit = {}) {
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

/// Adds to `into` the params of `reads` it does not hold yet.
void add_reads(ParamReads& into, const ParamReads& reads) {
  for (const ValueDecl* d : reads)
    if (std::find(into.begin(), into.end(), d) == into.end()) into.push_back(d);
}

} // namespace

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

NetworkSpec Elaborator::run() {
  return run_near(nullptr, {}, nullptr);
}

NetworkSpec Elaborator::run_near(const ElaborationRecord* from, const ParamReads& moved,
                                 std::optional<ElaborationRecord>* record) {
  NetworkSpec net;
  net.model = m_.name();
  ElaborationRecord r;
  recording_ = record != nullptr;
  if (case_) apply_param_overrides();
  elaborate_declarations(net, from, moved, record ? &r : nullptr);
  recording_ = false;
  if (record) {
    record->reset();
    if (references_.empty()) { // (a value reading another key is resolved with the case's settings)
      r.declared = net;
      r.element_slot = element_slot_;
      *record = std::move(r);
    }
  }
  finish(net);
  return net;
}

void Elaborator::elaborate_declarations(NetworkSpec& net, const ElaborationRecord* from,
                                        const ParamReads& moved, ElaborationRecord* into) {
  // A declaration is copied from the record when it read none of the moved params.
  const auto copied = [&](const ParamReads& reads) {
    return std::none_of(reads.begin(), reads.end(), [&](const ValueDecl* d) {
      return std::find(moved.begin(), moved.end(), d) != moved.end();
    });
  };
  const auto& nodes = m_.nodes();
  net.nodes.resize(nodes.size());
  if (into) into->node_reads.assign(nodes.size(), {});
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (from && copied(from->node_reads[i])) {
      net.nodes[i] = from->declared.nodes[i];
      if (into) into->node_reads[i] = from->node_reads[i];
      continue;
    }
    ParamReads reads;
    {
      Reading reading(*this, reads);
      elaborate_node(nodes[i], net.nodes[i]);
    }
    if (into) into->node_reads[i] = std::move(reads);
  }
  const auto& elements = m_.elements();
  element_slot_.assign(elements.size(), -1);
  net.elements.reserve(elements.size());
  if (into) into->element_reads.assign(elements.size(), {});
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const ElementDecl& d = elements[i];
    if (from && copied(from->element_reads[i])) {
      if (const int slot = from->element_slot[i]; slot >= 0) {
        element_slot_[i] = static_cast<int>(net.elements.size());
        net.elements.push_back(from->declared.elements[static_cast<std::size_t>(slot)]);
      }
      if (into) into->element_reads[i] = from->element_reads[i];
      continue;
    }
    ParamReads reads;
    std::optional<ElementSpec> e;
    {
      Reading reading(*this, reads);
      e = d.element ? elaborate_element(d) : elaborate_composite(d);
    }
    if (into) into->element_reads[i] = std::move(reads);
    if (!e) continue;
    element_slot_[i] = static_cast<int>(net.elements.size());
    net.elements.push_back(std::move(*e));
  }
}

// The case's settings, the values set from outside the model over them, and the requirements that
// apply to the case.
void Elaborator::finish(NetworkSpec& net) {
  if (case_) apply_case(net);
  apply_key_settings(net);
  drop_unresolved_lags(net);
  resolve_references(net);
  add_requirements(net);
}

// A lag far shorter than the run is invisible in every output, and the integrators cannot resolve
// it (IDA's consistent start fails on the derivative of so stiff a state): it is taken as none,
// with a warning, as the element itself would take it.
void Elaborator::drop_unresolved_lags(NetworkSpec& net) {
  for (ElementSpec& e : net.elements) {
    if (!e.schema) continue;
    for (const KeySchema& k : e.schema->keys) {
      if (!k.lag) continue;
      auto it = e.values.find(k.name);
      if (it == e.values.end() || !it->second.is_constant()) continue;
      const double lag = it->second.constant;
      if (!unresolved_lag(lag, net.settings.duration)) continue;
      const Span at{e.where.file, e.where.begin, e.where.begin};
      const bool by_duration = std::isfinite(1.0 / lag) && net.settings.duration;
      report(DiagnosticEngine::make(
          DiagId::lag_unresolved, at, e.where, e.kind(), e.name, k.name, fmt::format("{:g}", lag),
          by_duration ? fmt::format("shorter than 1e-7 of the {:g} s of case '{}'",
                                    *net.settings.duration, net.settings.name)
                      : std::string("too short for any run")));
      it->second = Signal::of(0.0);
    }
  }
}

// Keys set from outside the model come last, over the model's and the case's values; the objects
// and keys were checked by Model::settable_key(), the values against the keys' ranges.
void Elaborator::apply_key_settings(NetworkSpec& net) {
  for (const KeySetting& s : external_->keys) {
    supersede(s.object, s.key);
    if (const int n = m_.node_index(s.object); n >= 0) {
      NodeSpec& node = net.nodes[static_cast<std::size_t>(n)];
      if (s.key == "T")
        node.T = Signal::of(s.value);
      else if (s.key == "C")
        node.C = s.value;
      else
        node.T0 = s.value;
      continue;
    }
    const int decl = m_.element_index(s.object);
    if (decl < 0) continue;
    const int slot = element_slot_[static_cast<std::size_t>(decl)];
    if (slot < 0) continue; // the element has errors, reported
    ElementSpec& e = net.elements[static_cast<std::size_t>(slot)];
    const Span at{e.where.file, e.where.begin, e.where.begin};
    const bool in_group =
        std::any_of(e.schema->alternatives.begin(), e.schema->alternatives.end(),
                    [&](const auto& g) { return std::find(g.begin(), g.end(), s.key) != g.end(); });
    if (in_group && !e.has(s.key)) {
      report(DiagnosticEngine::make(
          DiagId::conflicting_keys, at, std::nullopt,
          fmt::format("{}: {} '{}' is not given by '{}' here, so its value cannot be replaced "
                      "(set the keys it is given by)",
                      s.option, e.kind(), e.name, s.key)));
      continue;
    }
    e.set(s.key, Signal::of(s.value));
    if (e.schema->check)
      for (const auto& problem : e.schema->check(e.key_values()))
        report(DiagnosticEngine::make(
            DiagId::conflicting_keys, at, std::nullopt,
            fmt::format("{}: {} '{}': {}", s.option, e.kind(), e.name, problem.message)));
  }
}

NetworkSpec Elaborator::run_on(NetworkSpec net, const Elaborator& base) {
  element_slot_ = base.element_slot_;
  finish(net); // the base's requirements are those of no case: replaced
  return net;
}

bool Elaborator::sets_params(const CaseDecl& c) {
  return std::any_of(c.stmt->items.begin(), c.stmt->items.end(), [](const ast::CaseItem& item) {
    const auto* a = std::get_if<ast::CaseAssign>(&item);
    return a && a->target.path.plain() && !is_case_key(a->target.path.id.name);
  });
}

void Elaborator::apply_case(NetworkSpec& net) {
  CaseSettings& s = net.settings;
  s.name = case_->name;
  s.where = case_->where;
  std::set<std::string> seen;
  set_keys_.clear();
  case_iterations_ = 0;
  case_loops_cut_ = false;
  failed_case_loops_.clear();
  apply_case_items(net, case_->stmt->items, nullptr, seen);
  if (!seen.count("duration") && !case_->stmt->unparsed_duration) // (else its syntax error)
    report(DiagnosticEngine::make(DiagId::missing_duration,
                                  Span{case_->file, s.where.begin, s.where.begin}, case_->name_span,
                                  s.name));
  else if (data_times_)
    warn_data_beyond_duration(s);
  if (s.initial_data) initial_from_data(net);
  check_output_times(s);
}

void Elaborator::check_output_times(const CaseSettings& s) {
  if (s.output_times.empty() || !s.duration || s.output_times.back() <= *s.duration) return;
  for (const auto& item : case_->stmt->items) {
    const auto* a = std::get_if<ast::CaseAssign>(&item);
    if (!a || !a->target.path.plain() || a->target.path.id.name != "output" || a->more.empty())
      continue;
    const auto late = std::upper_bound(s.output_times.begin(), s.output_times.end(), *s.duration);
    const auto k = static_cast<std::size_t>(late - s.output_times.begin());
    const ast::Expr& e = k == 0 ? *a->value.as_expr() : a->more[k - 1];
    report(DiagnosticEngine::make(DiagId::out_of_range, Span{case_->file, a->begin, a->begin},
                                  span_of(case_->file, e),
                                  fmt::format("a time of 'output' of case '{}'", s.name),
                                  fmt::format("at most the case's duration ({:g} s)", *s.duration),
                                  fmt::format("{:g} s", *late)));
    return;
  }
}

void Elaborator::apply_case_items(NetworkSpec& net, const std::vector<ast::CaseItem>& items,
                                  const Scope* scope, std::set<std::string>& seen) {
  const FileId f = case_->file;
  for (const auto& item : items) {
    if (const auto* loop = std::get_if<ast::CaseFor>(&item)) {
      if (failed_case_loops_.count(loop)) continue; // a bound was wrong: reported once
      // A loop over settings: each iteration applies its items with the loop's variables.
      Scope partial = Scope::loop(scope, f, loop->begin, loop->ranges);
      const auto bounds = [&](std::size_t k) -> std::optional<LoopBounds> {
        Restore<const Scope*> context(context_, scope);
        try {
          const long lo =
              whole_number(loop->ranges[k].lo, f, &partial, "the first value of a loop");
          const long hi = whole_number(loop->ranges[k].hi, f, &partial, "the last value of a loop");
          if (hi < lo || afford_case_iterations(static_cast<std::size_t>(hi - lo) + 1,
                                                Span{f, loop->begin, loop->begin},
                                                span_of(f, loop->ranges[k])))
            return LoopBounds{lo, hi};
          return std::nullopt;
        } catch (const EvalError& e) {
          // Reported once: the loop runs no more in this case, in any iteration of those around
          // it (a wrong bound inside 20 nested loops would otherwise be evaluated a million times).
          if (!e.diag.code.empty()) report(e.diag);
          failed_case_loops_.insert(loop);
          return std::nullopt;
        }
      };
      for_each_iteration(
          loop->ranges.size(), partial.values, bounds, [] { return true; },
          [&] {
            apply_case_items(net, loop->items, &partial, seen);
            return !case_loops_cut_; // past the limit, the loops around stop too
          });
      continue;
    }
    Restore<const Scope*> context(context_, scope);
    if (const auto* data = std::get_if<ast::CaseData>(&item)) {
      apply_data(net, *data, scope, seen);
      continue;
    }
    const auto& a = std::get<ast::CaseAssign>(item);
    if (a.target.path.rest().empty() && !a.target.path.plain()) {
      report(DiagnosticEngine::make(
          DiagId::override_fixed_only, Span{f, a.begin, a.begin}, span_of(f, a.target),
          fmt::format("'{}' sets no key: a case sets 'NAME.KEY = ...' of a node, boundary or "
                      "element, or 'PARAM = ...'",
                      std::string_view(m_.sources().text(f))
                          .substr(a.target.begin, a.target.end - a.target.begin))));
      continue;
    }
    if (!a.target.path.plain()) {
      apply_override(net, a, scope);
      continue;
    }
    const std::string_view key = a.target.path.id.name;
    if (!is_case_key(key)) {
      if (scope)
        report(DiagnosticEngine::make(DiagId::misplaced_statement, Span{f, a.begin, a.begin},
                                      span_of(f, a.target),
                                      "a param is set once per case, not in a loop"));
      continue; // params: done in apply_param_overrides()
    }
    if (scope) {
      report(DiagnosticEngine::make(DiagId::misplaced_statement, Span{f, a.begin, a.begin},
                                    span_of(f, a.target),
                                    fmt::format("'{}' is set once per case, not in a loop", key)));
      continue;
    }
    apply_setting(net, a, seen);
  }
}

bool Elaborator::afford_case_iterations(std::size_t n, Span at, Span mark) {
  const std::size_t limit = m_.max_case_iterations();
  if (n <= limit - case_iterations_) {
    case_iterations_ += n;
    return true;
  }
  case_iterations_ = limit;
  if (!std::exchange(case_loops_cut_, true)) // once per case, where the limit was passed
    report(DiagnosticEngine::make(
        DiagId::bad_loop, at, mark,
        fmt::format("the loops of a case may run at most {} times in all", limit)));
  return false;
}

bool Elaborator::first_setting(const std::string& name, Span at, Span mark) {
  const auto [it, fresh] = set_keys_.emplace(name, std::pair{mark, false});
  if (fresh) return true;
  // Once per key: a loop setting it in 5,000,000 iterations would build as many messages.
  if (std::exchange(it->second.second, true)) return false;
  Diagnostic d = DiagnosticEngine::make(DiagId::duplicate_case_key, at, mark, case_->name, name);
  d.notes.push_back(DiagnosticEngine::note(DiagId::note_text, it->second.first, "first set here"));
  report(std::move(d));
  return false;
}

void Elaborator::apply_setting(NetworkSpec& net, const ast::CaseAssign& a,
                               std::set<std::string>& seen) {
  static const KeySchema positive_time = builtin_key("", dim::time, true, "");
  static const KeySchema absolute = temperature_key("", "");
  const FileId f = case_->file;
  CaseSettings& s = net.settings;
  const std::string key(a.target.path.id.name);
  Span at{f, a.begin, a.begin};
  if (!seen.insert(key).second) {
    report(
        DiagnosticEngine::make(DiagId::duplicate_case_key, at, span_of(f, a.target), s.name, key));
    return;
  }
  const ast::Expr* e = a.value.as_expr();
  if (!a.more.empty() && key != "output") {
    report(DiagnosticEngine::make(DiagId::list_not_allowed, at, span_of(f, a.more.front()),
                                  fmt::format("'{}' of case '{}'", key, s.name)));
    return;
  }
  if (!e) {
    report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, span_of(f, a.target),
                                  fmt::format("'{}' of case '{}'", key, s.name)));
    return;
  }
  if (key == "initial") {
    const ast::Identifier* id = as_identifier(a.value, m_.file(f));
    if (id && id->name == "steady" && !value_decls_.count("steady")) {
      s.initial_steady = true;
      return;
    }
    if (id && id->name == "data" && !value_decls_.count("data")) {
      s.initial_data = true;
      return;
    }
    s.initial = number(*e, f,
                       Place{[&] { return fmt::format("'initial' of case '{}'", s.name); },
                             dim::temperature, true, &absolute},
                       at);
    return;
  }
  if (key == "duration") {
    s.duration = number(*e, f,
                        Place{[&] { return fmt::format("'duration' of case '{}'", s.name); },
                              dim::time, false, &positive_time},
                        at);
    return;
  }
  // `output = DT` is an interval; `output = t1, t2, ...` lists the times to write.
  if (a.more.empty()) {
    s.output = number(*e, f,
                      Place{[&] { return fmt::format("'output' of case '{}'", s.name); }, dim::time,
                            false, &positive_time},
                      at);
    return;
  }
  static const KeySchema time_point = builtin_key("", dim::time, false, "");
  std::vector<double> times;
  bool ok = true;
  std::vector<const ast::Expr*> items{e};
  for (const auto& m : a.more)
    items.push_back(&m);
  for (const ast::Expr* x : items) {
    auto t = number(*x, f,
                    Place{[&] { return fmt::format("a time of 'output' of case '{}'", s.name); },
                          dim::time, false, &time_point},
                    at);
    if (!t) {
      ok = false;
      continue;
    }
    if (!times.empty() && !(*t > times.back())) {
      report(DiagnosticEngine::make(
          DiagId::bad_signal, at, span_of(f, *x),
          fmt::format("output times must increase: {:g} s follows {:g} s", *t, times.back())));
      ok = false;
      continue;
    }
    times.push_back(*t);
  }
  if (ok) s.output_times = std::move(times);
}

std::string case_param_name(std::string_view node, std::string_view case_name) {
  return fmt::format("{}.T0@{}", node, case_name);
}

std::optional<std::pair<double, double>> Elaborator::case_range(const ast::Range& r, const Place& p,
                                                                Span at) {
  const FileId f = case_->file;
  auto lo = number(r.lo, f, p, at);
  auto hi = number(r.hi, f, p, at);
  if (!lo || !hi) return std::nullopt;
  if (!(*lo < *hi)) {
    const auto shown = compared_numbers({*lo - kZeroCelsius, *hi - kZeroCelsius}, " degC");
    report(DiagnosticEngine::make(DiagId::bad_range, at, span_of(f, r), "start temperature",
                                  shown[0], shown[1]));
    return std::nullopt;
  }
  return std::make_pair(*lo, *hi);
}

void Elaborator::apply_override(NetworkSpec& net, const ast::CaseAssign& a, const Scope* scope) {
  const FileId f = case_->file;
  Span at{f, a.begin, a.begin};
  const ast::Ref& path = a.target.path;
  // The last part is the key; the parts before it name the node, boundary or element.
  const ast::Ref& last = path.rest().back();
  const std::string key(last.id.name);
  Span key_span = span_of(f, last);
  std::string obj;
  try {
    obj = std::string(path.id.name);
    if (!path.index().empty() || path.rest().size() > 1 || !last.index().empty()) {
      // The name of the object: every part but the key, indices evaluated.
      obj = reference_text(path, f, scope);
      obj.resize(obj.size() - last.id.name.size() - 1);
      if (!last.index().empty())
        throw EvalError(DiagnosticEngine::make(DiagId::bad_index, key_span, key_span,
                                               "the key of a case setting has no index"));
    }
  } catch (const EvalError& e) {
    if (!e.diag.code.empty()) {
      Diagnostic d = e.diag;
      d.at = at;
      report(std::move(d));
    }
    return;
  }
  const Span object_span{f, path.begin,
                         path.rest().size() > 1 ? path.rest()[path.rest().size() - 2].end
                                                : path.id.end};
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
            ks->absolute_temperature, ks, ks->type == KeyType::signal};
    if (!a.more.empty()) {
      report(DiagnosticEngine::make(DiagId::list_not_allowed, at, span_of(f, a.more.front()),
                                    p.what()));
      return;
    }
    if (ks->type == KeyType::number && !a.value.as_expr()) {
      report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, key_span, p.what()));
      return;
    }
    if (!first_setting(obj + '.' + key, at, span_of(f, a.target))) return;
    auto v = signal(a.value, f, p, at, obj);
    if (!v) return;
    if (a.range) {
      if (key != "T0" || scope) {
        report(DiagnosticEngine::make(
            DiagId::override_fixed_only, at, span_of(f, *a.range),
            "a range in a case makes a node's start temperature unknown per case (NODE.T0 = "
            "VALUE range LO .. HI), once per case, not in a loop"));
        return;
      }
      auto range = case_range(*a.range, p, at);
      if (!range) return;
      const std::string name = case_param_name(obj, case_->name);
      if (auto o = overrides_.find(name); o != overrides_.end()) v = Signal::of(o->second);
      if (v->constant < range->first || v->constant > range->second) {
        const auto shown = compared_numbers(
            {v->constant - kZeroCelsius, range->first - kZeroCelsius, range->second - kZeroCelsius},
            " degC");
        report(DiagnosticEngine::make(DiagId::param_outside_range, at, span_of(f, a.value.span()),
                                      name, shown[0], shown[1], shown[2]));
        return;
      }
    }
    if (key == "T")
      node.T = *v;
    else if (key == "C")
      node.C = v->constant;
    else
      node.T0 = v->constant;
    return;
  }
  if (a.range) {
    report(DiagnosticEngine::make(
        DiagId::override_fixed_only, at, span_of(f, *a.range),
        "a range in a case makes a node's start temperature unknown per case (NODE.T0 = VALUE "
        "range LO .. HI); an element's key is calibrated through a ranged param of the model"));
    return;
  }
  const int decl = m_.element_index(obj);
  if (decl < 0 && m_.declared_by_unparsed(path.id.name)) return;
  if (decl < 0) {
    if (m_.instance(obj)) {
      report(DiagnosticEngine::make(
          DiagId::override_fixed_only, at, span_of(f, a.target),
          fmt::format("a case cannot set the params of instance '{}'; give the instance a "
                      "fixed param of the model ('{} = NAME') and set that param in the case",
                      obj, key)));
      return;
    }
    Diagnostic d = DiagnosticEngine::make(DiagId::unknown_element, at, object_span, obj);
    suggest(d, obj, [&] {
      std::vector<std::string> names;
      for (const auto& e : m_.elements())
        names.emplace_back(e.name);
      for (const auto& nd : m_.nodes())
        names.emplace_back(nd.name);
      return names;
    });
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
                                          fmt::format("element kind '{}'", e.kind()), key);
    if (ks) // a node-valued key such as 'sense' is part of the wiring, not a value
      d.notes.push_back(DiagnosticEngine::note(
          DiagId::note_text, std::nullopt,
          fmt::format("'{}' names a node and cannot be set by a case", key)));
    else if (auto s = closest_match(key, names))
      d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
    else
      d.notes.push_back(
          DiagnosticEngine::note(DiagId::note_text, std::nullopt,
                                 fmt::format("'{}' takes: {}", e.kind(), list_names(names))));
    report(std::move(d));
    return;
  }
  Place p{[&] { return fmt::format("{} of {} '{}'", key, e.kind(), e.name); }, ks->dim,
          ks->absolute_temperature, ks, ks->type == KeyType::signal};
  if (!a.more.empty()) {
    report(
        DiagnosticEngine::make(DiagId::list_not_allowed, at, span_of(f, a.more.front()), p.what()));
    return;
  }
  if (ks->type == KeyType::number && !a.value.as_expr()) {
    report(DiagnosticEngine::make(DiagId::signal_not_allowed, at, key_span, p.what()));
    return;
  }
  if (!first_setting(obj + '.' + key, at, span_of(f, a.target))) return;
  if (auto v = signal(a.value, f, p, at, e.name)) e.values[*ks] = std::move(*v);
}

} // namespace thermnet::lang
