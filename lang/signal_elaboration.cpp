// The elaboration of values that change over time: step/pwl signals, tables of CSV files (linear
// or held, in the files' own layout), expressions of the time and of signals (`Aw * table(...)`).

#include "lang/display_text.hpp"
#include "lang/elaborator.hpp"
#include "lang/elaborator_detail.hpp"
#include "lang/time_program.hpp"
#include "lang/units.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

namespace thermnet::lang {
using namespace detail;

namespace {

namespace fs = std::filesystem;

/// The place of a signal's corner times.
const KeySchema& any_time() {
  static const KeySchema k = [] {
    KeySchema s;
    s.dim = dim::time;
    return s;
  }();
  return k;
}

/// True when the expression reads another element's key (`film.P`).
bool reads_key(const ast::File& file, ast::Index root) {
  std::vector<ast::Index> stack{root};
  while (!stack.empty()) {
    const ast::ExprNode& n = file.node(stack.back());
    stack.pop_back();
    switch (n.op) {
    case ast::ExprNode::Op::ref:
      return true;
    case ast::ExprNode::Op::negate:
    case ast::ExprNode::Op::group:
      stack.push_back(n.a);
      break;
    case ast::ExprNode::Op::add:
    case ast::ExprNode::Op::subtract:
    case ast::ExprNode::Op::multiply:
    case ast::ExprNode::Op::divide:
    case ast::ExprNode::Op::power:
      stack.push_back(n.a);
      stack.push_back(n.b);
      break;
    case ast::ExprNode::Op::call:
      for (ast::Index arg : file.call_args(n))
        stack.push_back(arg);
      break;
    default:
      break;
    }
  }
  return false;
}

} // namespace

std::optional<Signal> Elaborator::signal(const ast::Value& v, FileId f, const Place& p, Span at,
                                         std::string_view owner) {
  const ast::File& file = m_.file(f);
  const bool reference =
      v.as_reference() ? !v.as_reference()->rest().empty() : reads_key(file, v.expr.root);
  if (!owner.empty() && !net_ && p.key) supersede(owner, p.key->name); // a later value wins
  if (reference && p.time_allowed && !owner.empty() && !net_) {
    defer(v, f, p, at, owner); // elaborated when every key is final (resolve_references)
    return Signal::of(p.absolute_temperature ? 293.15 : 0.0); // a valid stand-in until then
  }
  if (v.as_reference() && !(reference && p.time_allowed && net_)) {
    report(
        DiagnosticEngine::make(DiagId::syntax_expected, at, span_of(f, v.span()),
                               fmt::format("expected a value for {}, not a node name", p.what())));
    return std::nullopt;
  }
  if (const ast::Ref* r = v.as_reference()) { // `P = film.P`: that key's value as it is
    try {
      Signal out;
      referenced_key(*r, f, context_, span_of(f, *r), out);
      const Span mark = span_of(f, *r);
      for (double x : out.is_constant() ? std::vector<double>{out.constant} : out.values())
        if (!check_range(x, p, at, mark)) return std::nullopt;
      if (out.kind() == Signal::Kind::expression && !check_range(out.at(0.0), p, at, mark))
        return std::nullopt;
      return out;
    } catch (const EvalError& err) {
      report_at(err, at);
      return std::nullopt;
    }
  }
  const ast::Expr& e = v.expr;
  if (p.time_allowed && file.node(e.root).op == ast::ExprNode::Op::signal)
    return whole_signal(file.signals[file.node(e.root).a], f, p, at);
  if (p.time_allowed) return expression_signal(e, f, p, at);
  auto x = number(e, f, p, at);
  return x ? std::optional<Signal>(Signal::of(*x)) : std::nullopt;
}

// A value that is one signal keeps its corners: each point is converted to the place on its own
// (a bare temperature is degC), and every value is checked against the key's range.
std::optional<Signal> Elaborator::whole_signal(const ast::SignalExpr& se, FileId f, const Place& p,
                                               Span at) {
  if (const auto* ts = std::get_if<ast::TableSignal>(&se)) {
    auto table = table_values(*ts, f, at);
    if (!table) return std::nullopt;
    Signal s = std::move(table->signal);
    if (table->dim && !(*table->dim == p.dim)) {
      report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_of(f, *ts), p.what(),
                                    describe(p.dim), describe(*table->dim)));
      return std::nullopt;
    }
    if (!table->dim && p.absolute_temperature) { // bare temperatures are degC
      s.constant += kZeroCelsius;                // (`table(data, ...)` outside a case: 0 degC)
      if (!s.is_constant())
        for (double& x : s.shape().v)
          x += kZeroCelsius;
    }
    if (s.is_constant()) return s;
    for (double x : s.values())
      if (!check_range(x, p, at, span_of(f, *ts))) return std::nullopt;
    s.shape().at = at; // (a run that its rows make fail names the table)
    s.shape().mark = span_of(f, *ts);
    return s;
  }
  const auto& ps = std::get<ast::PointSignal>(se);
  Signal s;
  s.shape(ps.kind.name == "step" ? Signal::Kind::step : Signal::Kind::pwl);
  Place time{[&] { return fmt::format("a time in the {} signal of {}", ps.kind.name, p.what()); },
             dim::time, false, &any_time()};
  bool ok = true;
  for (const auto& pt : ps.points) {
    auto t = number(pt.time, f, time, at);
    auto x = number(pt.value, f, p, at);
    if (!t || !x) {
      ok = false;
      continue;
    }
    Signal::Shape& corners = s.shape();
    if (!corners.t.empty() && !(*t > corners.t.back())) {
      report(DiagnosticEngine::make(
          DiagId::bad_signal, at, span_of(f, pt.time),
          fmt::format("signal times must increase: {:g} s follows {:g} s", *t, corners.t.back())));
      ok = false;
      continue;
    }
    corners.t.push_back(*t);
    corners.v.push_back(*x);
  }
  if (!ok) return std::nullopt;
  s.shape().at = at;
  s.shape().mark = span_of(f, ps);
  return s;
}

// An expression that uses `time` or signals becomes a program of the time; its unit is checked by
// evaluating it once (at t = 0), and its value is checked at t = 0.
std::optional<Signal> Elaborator::expression_signal(const ast::Expr& e, FileId f, const Place& p,
                                                    Span at) {
  Quantity q;
  // A reference may elaborate another value meanwhile (resolve()): this one's state is its own.
  std::unordered_map<ast::Index, Signal> outer_embedded;
  std::swap(outer_embedded, embedded_);
  struct Back {
    std::unordered_map<ast::Index, Signal>& outer;
    std::unordered_map<ast::Index, Signal>& embedded;
    ~Back() { std::swap(outer, embedded); }
  } back{outer_embedded, embedded_};
  try {
    Restore<bool> time(time_allowed_, true);
    Restore<bool> seen(saw_time_, false);
    Restore<Span> statement(statement_at_, at);
    q = evaluator(f, context_).eval(e);
    if (!saw_time_) {
      auto v = to_place(q, p, at, span_of(f, e));
      return v ? std::optional<Signal>(Signal::of(*v)) : std::nullopt;
    }
    if (q.dim && !(*q.dim == p.dim)) {
      report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_of(f, e), p.what(),
                                    describe(p.dim), describe(*q.dim)));
      return std::nullopt;
    }
    Signal s;
    const Scope* scope = context_;
    Signal::Shape& shape = s.shape(Signal::Kind::expression);
    shape.program = compile_time_program(
        m_.file(f), e.root, [&](const ast::Identifier& id) { return lookup(id, f, scope).value; },
        [&](ast::Index node) { return embedded_.at(node); });
    shape.t = shape.program->corners();
    shape.offset = bare_temperature_offset(q, p.absolute_temperature);
    shape.at = at;
    shape.mark = span_of(f, e);
    if (!check_range(s.at(0.0), p, at, span_of(f, e))) return std::nullopt;
    return s;
  } catch (const EvalError& err) {
    report_at(err, at);
    return std::nullopt;
  }
}

// A signal standing in an expression: built once per evaluation (kept for the compiled program),
// its value at t = 0 and its dimension returned to the evaluator. Its values are SI numbers of
// the unit written (bare numbers stay bare: the whole expression takes the place's unit).
Quantity Elaborator::embedded_signal(ast::Index node, FileId f, const Scope* scope) {
  const ast::File& file = m_.file(f);
  const ast::ExprNode& n = file.node(node);
  const Span mark = span_of(f, n);
  if (!time_allowed_) {
    if (constant_place_)
      throw EvalError(
          DiagnosticEngine::make(DiagId::signal_not_allowed, mark, mark, constant_place_->what()));
    throw EvalError(DiagnosticEngine::make(
        DiagId::signal_misplaced, mark, mark,
        n.op == ast::ExprNode::Op::ref ? "a key of another element" : "a signal"));
  }
  saw_time_ = true;
  if (n.op == ast::ExprNode::Op::ref) {
    if (!net_)
      throw EvalError(DiagnosticEngine::make(
          DiagId::bad_signal, mark, mark,
          "a reference to another element's key stands only in the value of a key that may "
          "change over time (a boundary's T, a source's power, a switch)"));
    Signal s;
    const Quantity q = referenced_key(file.expr_refs[n.a], f, scope, mark, s);
    embedded_.insert_or_assign(node, std::move(s));
    return q;
  }
  const ast::SignalExpr& se = file.signals[n.a];
  Signal s;
  std::optional<Dimension> dim;
  if (const auto* ts = std::get_if<ast::TableSignal>(&se)) {
    auto table = table_values(*ts, f, statement_at_);
    if (!table) throw EvalError(Diagnostic{}); // reported
    s = std::move(table->signal);
    dim = table->dim;
  } else {
    const auto& ps = std::get<ast::PointSignal>(se);
    Restore<bool> no_time(time_allowed_, false); // no signal inside a signal
    Evaluator ev = evaluator(f, scope);
    s.shape(ps.kind.name == "step" ? Signal::Kind::step : Signal::Kind::pwl);
    bool first = true;
    for (const auto& pt : ps.points) {
      const Quantity t = ev.eval(pt.time);
      if (t.dim && !(*t.dim == dim::time))
        throw EvalError(DiagnosticEngine::make(DiagId::unit_mismatch, span_of(f, pt.time),
                                               span_of(f, pt.time),
                                               fmt::format("a time in the {} signal", ps.kind.name),
                                               describe(dim::time), describe(*t.dim)));
      const Quantity x = ev.eval(pt.value);
      if (x.dim && dim && !(*x.dim == *dim))
        throw EvalError(DiagnosticEngine::make(DiagId::unit_mix, span_of(f, pt.value),
                                               span_of(f, pt.value), "combine", describe(*dim),
                                               describe(*x.dim)));
      if (x.dim) dim = x.dim;
      Signal::Shape& corners = s.shape();
      if (!first && !(t.value > corners.t.back()))
        throw EvalError(
            DiagnosticEngine::make(DiagId::bad_signal, span_of(f, pt.time), span_of(f, pt.time),
                                   fmt::format("signal times must increase: {:g} s follows {:g} s",
                                               t.value, corners.t.back())));
      first = false;
      corners.t.push_back(t.value);
      corners.v.push_back(x.value);
    }
  }
  const double at0 = s.at(0.0);
  embedded_.insert_or_assign(node, std::move(s));
  return Quantity{at0, dim};
}

void Elaborator::defer(const ast::Value& v, FileId f, const Place& p, Span at,
                       std::string_view owner) {
  std::string kind = p.what();
  kind = kind.substr(kind.find(" of ") + 4);
  kind = kind.substr(0, kind.find(' '));
  references_.push_back(
      KeyReference{std::string(owner), kind, p.key, &v, f, context_, at, false, false});
  reference_of_[fmt::format("{}.{}", owner, p.key->name)].push_back(references_.size() - 1);
}

void Elaborator::supersede(std::string_view owner, std::string_view key) {
  if (references_.empty()) return;
  if (const auto it = reference_of_.find(fmt::format("{}.{}", owner, key));
      it != reference_of_.end())
    for (const std::size_t i : it->second)
      references_[i].done = true;
}

// Every value that reads another key, once the case and the values set from outside the model
// have set every key: a reference to a key that reads another is elaborated after that one, and
// a chain that comes back is a cycle.
void Elaborator::resolve_references(NetworkSpec& net) {
  if (references_.empty()) return;
  Restore<NetworkSpec*> network(net_, &net);
  for (auto& r : references_)
    resolve(r);
}

void Elaborator::resolve(KeyReference& r) {
  if (r.done) return;
  Restore<std::size_t> depth(resolve_depth_, resolve_depth_ + 1);
  r.resolving = true;
  Restore<const Scope*> context(context_, r.scope);
  const std::string what = fmt::format("{} of {} '{}'", r.key->name, r.kind, r.owner);
  Place p{[&] { return what; }, r.key->dim, r.key->absolute_temperature, r.key, true};
  std::optional<Signal> v = signal(*r.value, r.file, p, r.at, r.owner);
  r.resolving = false;
  r.done = true;
  if (!v) return;
  if (const int n = m_.node_index(r.owner); n >= 0) {
    net_->nodes[static_cast<std::size_t>(n)].T = std::move(*v);
    return;
  }
  const int decl = m_.element_index(r.owner);
  const int slot = decl >= 0 ? element_slot_[static_cast<std::size_t>(decl)] : -1;
  if (slot >= 0) net_->elements[static_cast<std::size_t>(slot)].values[*r.key] = std::move(*v);
}

// The value of `OBJECT.KEY` as the network has it now (a reference that is itself pending is
// elaborated first); only values that may change over time can be read: a boundary's T and the
// signal keys of elements.
Quantity Elaborator::referenced_key(const ast::Ref& ref, FileId f, const Scope* scope, Span mark,
                                    Signal& out) {
  std::string full = reference_text(ref, f, scope);
  const std::size_t dot = full.rfind('.');
  const std::string key = full.substr(dot + 1);
  std::string object = full.substr(0, dot);
  if (const Scope* inst = scope ? scope->instance() : nullptr) object = inst->prefix + object;
  const auto fail = [&](std::string message) {
    throw EvalError(DiagnosticEngine::make(DiagId::bad_signal, mark, mark, std::move(message)));
  };
  if (const auto it = reference_of_.find(fmt::format("{}.{}", object, key));
      it != reference_of_.end())
    for (const std::size_t i : it->second) {
      KeyReference& r = references_[i];
      if (r.resolving)
        throw EvalError(DiagnosticEngine::make(
            DiagId::cycle, mark, mark, fmt::format("{}.{}", object, key),
            fmt::format("{}.{} reads itself through the keys it reads", object, key)));
      // Each key read through the next is a level of recursion: bound it (a hostile model's
      // chain of 20,000 keys overflowed the stack).
      if (!r.done && resolve_depth_ >= max_reference_depth)
        fail(fmt::format("'{}' is read through a chain of more than {} keys that read one another",
                         full, max_reference_depth));
      resolve(r);
    }
  if (const int n = m_.node_index(object); n >= 0) {
    const NodeSpec& node = net_->nodes[static_cast<std::size_t>(n)];
    if (!node.boundary || key != "T")
      fail(fmt::format("'{}' reads key '{}' of {} '{}'; only a boundary's T and the keys of "
                       "elements that may change over time can be read",
                       full, key, node.boundary ? "boundary" : "node", object));
    out = node.T;
    return Quantity{out.at(0.0), dim::temperature};
  }
  const int decl = m_.element_index(object);
  if (decl < 0) {
    Diagnostic d = DiagnosticEngine::make(DiagId::unknown_element, mark, mark, object);
    suggest(d, object, [&] {
      std::vector<std::string> names;
      for (const auto& e : m_.elements())
        names.emplace_back(e.name);
      for (const auto& nd : m_.nodes())
        if (nd.boundary) names.emplace_back(nd.name);
      return names;
    });
    throw EvalError(std::move(d));
  }
  const int slot = element_slot_[static_cast<std::size_t>(decl)];
  if (slot < 0) throw EvalError(Diagnostic{}); // the element has errors, reported
  const ElementSpec& e = net_->elements[static_cast<std::size_t>(slot)];
  const KeySchema* ks = e.schema ? e.schema->key(key) : nullptr;
  if (!ks || ks->type != KeyType::signal || !e.has(key))
    fail(fmt::format("'{}' reads key '{}' of {} '{}', which {}", full, key, e.kind(), object,
                     !ks                           ? "has no such key"
                     : ks->type != KeyType::signal ? "is not a value that may change over time"
                                                   : "is not given"));
  out = e.values.at(key);
  return Quantity{out.at(0.0),
                  ks->dim.dimensionless() ? std::nullopt : std::optional<Dimension>(ks->dim)};
}

std::optional<CsvLayout> Elaborator::layout_of(const ast::FileOptions& o, FileId f, Span at,
                                               bool table) {
  CsvLayout layout;
  bool ok = true;
  for (const ast::Tagged& m : o.misplaced) {
    std::string_view word = std::string_view(m_.sources().text(f)).substr(m.begin, m.end - m.begin);
    word = word.substr(0, word.find_first_of(" \t="));
    report(DiagnosticEngine::make(
        DiagId::bad_signal, at, span_of(f, m),
        (word == "hold" || word == "before") && !table
            ? fmt::format("'{}' applies to a table's column (table(\"FILE\", \"COLUMN\", {})), "
                          "not to a data file",
                          word, word == "hold" ? "hold" : "before = VALUE")
            : fmt::format("'{}' is given twice", word)));
  }
  if (o.time) {
    layout.time_column = o.time->column.text;
    layout.time_first = false;
    if (o.time->unit)
      if (auto problem = parse_time_format(o.time->unit->text, layout)) {
        report(DiagnosticEngine::make(DiagId::bad_signal, at, span_of(f, *o.time->unit), *problem));
        ok = false;
      }
  }
  if (o.separator) {
    const std::string& t = o.separator->text;
    if (t == "," || t == ";" || t == "|" || t == "\t")
      layout.separator = t[0];
    else if (t == "tab")
      layout.separator = '\t';
    else {
      report(DiagnosticEngine::make(
          DiagId::bad_signal, at, span_of(f, *o.separator),
          fmt::format("the separator is \",\", \";\", \"|\" or \"tab\", not \"{}\"",
                      excerpt_for_display(t))));
      ok = false;
    }
  }
  return ok ? std::optional<CsvLayout>(layout) : std::nullopt;
}

// The case's data file, as tables `table(data, ...)` and the comparison read it: its path, its
// layout and, for absolute time stamps, the epoch the case starts at (its first row).
const Elaborator::CaseDataFile* Elaborator::case_data_file() {
  if (case_data_resolved_) return case_data_ ? &*case_data_ : nullptr;
  case_data_resolved_ = true;
  if (!case_) return nullptr;
  const FileId f = case_->file;
  for (const auto& item : case_->stmt->items) {
    const auto* data = std::get_if<ast::CaseData>(&item);
    if (!data) continue;
    const Span at{f, data->begin, data->begin};
    CaseDataFile d;
    fs::path p(data->path.text);
    if (p.is_relative()) p = fs::path(m_.directory_of(f)) / p;
    d.path = p.lexically_normal().string();
    d.at = at;
    d.mark = span_of(f, data->path);
    Restore<const Scope*> top(context_, nullptr);
    auto layout = layout_of(data->options, f, at, false);
    if (!layout) return nullptr;
    d.layout = *layout;
    if (d.layout.absolute()) {
      try {
        auto table = m_.tables().get(d.path, d.layout);
        if (table->rows() > 0) d.epoch = table->time().front();
      } catch (const CsvError&) {
        // reported where the data statement is checked
      }
    }
    case_data_ = std::move(d);
    return &*case_data_;
  }
  return nullptr;
}

// The values of a table's column at its rows' times (relative to the case's start), in SI of the
// unit written after the table (bare without one); a held column keeps only the rows where its
// value changes. Problems are reported at `at`.
std::optional<Elaborator::TableValues> Elaborator::table_values(const ast::TableSignal& ts,
                                                                FileId f, Span at) {
  // How messages name the file: "'power.csv'", "the case's data file 'run.csv'".
  const std::string name =
      ts.case_data && first_data_statement()
          ? fmt::format("the case's data file '{}'", first_data_statement()->path.text)
          : fmt::format("'{}'", ts.file.text);
  std::optional<Unit> unit;
  if (ts.unit) {
    try {
      unit = parse_unit(ts.unit->text);
    } catch (const UnitError& e) {
      report(DiagnosticEngine::make(DiagId::unknown_unit, at, span_of(f, *ts.unit), e.what()));
      return std::nullopt;
    }
  }
  const std::optional<Dimension> dim = unit ? std::optional<Dimension>(unit->dim) : std::nullopt;
  std::string path;
  CsvLayout layout;
  Span file_mark = span_of(f, ts.case_data ? static_cast<const ast::Tagged&>(ts) : ts.file);
  double epoch = 0.0;
  if (ts.case_data) {
    if (!ts.options.time && !ts.options.separator && !ts.options.misplaced.empty()) {
      layout_of(ts.options, f, at, true); // `hold` or `before` twice: "'hold' is given twice"
      return std::nullopt;
    }
    if (ts.options.time || ts.options.separator) {
      report(DiagnosticEngine::make(
          DiagId::bad_signal, at, file_mark,
          "table(data, ...) reads the case's data file in the layout its data statement gives; "
          "write the time column and separator there"));
      return std::nullopt;
    }
    const CaseDataFile* d = case_data_file();
    if (!d) {
      if (!case_ && !m_.cases().empty()) return TableValues{Signal::of(0.0), dim};
      if (first_data_statement()) return std::nullopt;              // its problem is reported there
      if (case_ && case_->stmt->unparsed_data) return std::nullopt; // its syntax error is
      report(DiagnosticEngine::make(
          DiagId::bad_signal, at, file_mark,
          case_ ? fmt::format("table(data, ...) reads the case's data file, but case '{}' has no "
                              "data statement",
                              case_->name)
                : std::string("table(data, ...) reads the case's data file, but the model has no "
                              "case")));
      return std::nullopt;
    }
    path = d->path;
    layout = d->layout;
    epoch = d->epoch;
  } else {
    fs::path p(ts.file.text);
    if (p.is_relative()) p = fs::path(m_.directory_of(f)) / p;
    path = p.lexically_normal().string();
    auto l = layout_of(ts.options, f, at, true);
    if (!l) return std::nullopt;
    layout = *l;
  }
  try {
    auto table = m_.tables().get(path, layout);
    const int col = table->column_index(ts.column.text);
    if (col <= 0) {
      Diagnostic d = DiagnosticEngine::make(
          DiagId::bad_signal, at, span_of(f, ts.column),
          col == 0 ? fmt::format("column '{}' of {} is its time", ts.column.text, name)
                   : fmt::format("{} has no column '{}'", name, ts.column.text));
      if (auto s = closest_match(ts.column.text, table->columns))
        if (col < 0)
          d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *s));
      report(std::move(d));
      return std::nullopt;
    }
    try {
      table->check_column(static_cast<std::size_t>(col));
    } catch (const CsvError& e) { // a cell of this column: the data statement may not read it
      report(DiagnosticEngine::make(DiagId::data_format, at, file_mark, e.what()));
      return std::nullopt;
    }
    if (layout.absolute() && !(ts.case_data)) {
      const CaseDataFile* d = case_data_file();
      epoch = d && d->layout.absolute() ? d->epoch : (table->rows() ? table->time().front() : 0.0);
    }
    const double scale = unit ? unit->scale : 1.0;
    const double offset = unit ? unit->offset : 0.0;
    TableValues out{Signal{}, dim};
    Signal::Shape& corners = out.signal.shape(ts.hold ? Signal::Kind::step : Signal::Kind::pwl);
    if (ts.before) {
      // An event log starts with the first change: the value before it is given. It stands as a
      // corner at -infinity, so a held signal has it until the first row.
      if (!ts.hold) {
        report(DiagnosticEngine::make(
            DiagId::bad_signal, at, span_of(f, *ts.before),
            "'before' gives a held column's value before its first row (table(..., hold, before "
            "= 0)); a linear column keeps its first value"));
        return std::nullopt;
      }
      static const KeySchema any;
      Place place{[] { return std::string("the value before a table's first row"); }, Dimension{},
                  false, &any};
      auto b = number(*ts.before, f, place, at);
      if (!b) return std::nullopt;
      corners.t.push_back(-std::numeric_limits<double>::infinity());
      corners.v.push_back(scale * *b + offset);
    }
    const auto& cells = table->cells[static_cast<std::size_t>(col)];
    for (std::size_t r = 0; r < table->rows(); ++r) {
      const double x = cells[r];
      if (std::isnan(x)) continue;
      const double v = scale * x + offset;
      if (ts.hold && !corners.v.empty() && corners.v.back() == v) continue; // no change: no corner
      corners.t.push_back(table->time()[r] - epoch);
      corners.v.push_back(v);
    }
    if (corners.t.empty()) {
      report(DiagnosticEngine::make(
          DiagId::bad_signal, at, span_of(f, ts.column),
          fmt::format("column '{}' of {} has no values", ts.column.text, name)));
      return std::nullopt;
    }
    return out;
  } catch (const CsvError& e) {
    if (ts.case_data) return std::nullopt; // the data statement reports its file's problems
    if (e.row == 0)
      report(
          DiagnosticEngine::make(DiagId::data_unreadable, at, file_mark, ts.file.text, e.detail));
    else
      report(DiagnosticEngine::make(DiagId::data_format, at, file_mark, e.what()));
    return std::nullopt;
  }
}

} // namespace thermnet::lang
