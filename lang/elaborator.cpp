// The elaborator's driver: construction, diagnostics, the run over the declarations (nodes and
// elements in order, then the case) and the network's finishing touches. The values, elements and
// cases it elaborates are in elaborator_values.cpp, elaborator_elements.cpp and
// elaborator_cases.cpp.

#include "lang/elaborator.hpp"
#include "lang/elaborator_detail.hpp"

#include "lang/loop_iteration.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace thermnet::lang {
using namespace detail;

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

} // namespace thermnet::lang
