// The elaborator's cases: a case's settings (duration, initial, output), its overrides of
// elements, nodes and params, its loops, and the starts a case fits.

#include "lang/elaborator.hpp"
#include "lang/elaborator_detail.hpp"

#include "lang/loop_iteration.hpp"
#include "lang/units.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace thermnet::lang {
using namespace detail;

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
