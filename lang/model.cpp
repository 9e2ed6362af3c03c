// The Model's checking entry points: lint (collect everything), instantiate (throw at the first
// error), params, and the topology warnings lint adds.

#include "lang/model.hpp"
#include "lang/elaborator.hpp"
#include "lang/units.hpp"

#include <algorithm>
#include <numeric>
#include <set>
#include <tuple>
#include <unordered_map>

namespace thermnet::lang {
namespace {

/// Union-find over node indices.
struct Components {
  std::vector<int> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[static_cast<std::size_t>(i)] != i)
      i = parent[static_cast<std::size_t>(i)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    return i;
  }
  void join(int a, int b) { parent[static_cast<std::size_t>(find(a))] = find(b); }
};

Span start_of(const Span& s) {
  return Span{s.file, s.begin, s.begin};
}

/// "'a', 'b', 'c', 'd' and 7 more": the first four of some nodes, quoted, and how many others.
std::string quoted_names(const Model& m, const std::vector<std::size_t>& members) {
  std::string names;
  for (std::size_t k = 0; k < members.size() && k < 4; ++k)
    names += fmt::format("{}'{}'", k ? ", " : "", m.nodes()[members[k]].name);
  if (members.size() > 4) names += fmt::format(" and {} more", members.size() - 4);
  return names;
}

/// Warnings about the network's shape: isolated nodes, and groups with no path to a boundary.
/// Links are taken from the declarations, not from the elaborated network, so an element with an
/// error still links its nodes (its error is reported; a warning about its nodes would be noise).
/// A sensor's reading is a series of its own (a data file's column, an output column of
/// `simulate --sensors`): a sensor named like a node would make both columns one name.
void check_sensor_names(const Model& m, const Reporter& report) {
  for (const auto& e : m.elements()) {
    if (!e.schema || !e.schema->observes) continue;
    const int node = m.node_index(e.name);
    if (node < 0) continue;
    const NodeDecl& n = m.nodes()[static_cast<std::size_t>(node)];
    const Span where = e.where();
    Diagnostic d =
        DiagnosticEngine::make(DiagId::duplicate_name, Span{where.file, where.begin, where.begin},
                               e.name_span(), "sensor", e.name);
    d.message = fmt::format("sensor '{}' has the name of {} '{}': its reading is a column of its "
                            "own (in data files and simulate --sensors); name it otherwise",
                            e.name, n.boundary ? "boundary" : "node", e.name);
    d.notes.push_back(DiagnosticEngine::note(
        DiagId::note_text, n.name_span(),
        fmt::format("{} '{}' is declared here", n.boundary ? "boundary" : "node", e.name)));
    report(std::move(d));
  }
}

void check_topology(const Model& m, const Reporter& report) {
  const auto& decls = m.nodes();
  const std::size_t n = decls.size();
  // Index n stands for every unknown name: it counts as a boundary, so no group is called
  // floating because of a name that is already reported (or hidden by a syntax error).
  const int unknown = static_cast<int>(n);
  Components comp(n + 1);
  std::vector<int> degree(n + 1, 0);
  std::vector<int> ids;
  for (const auto& e : m.elements()) {
    if (e.nodes.size() < 2) continue;             // a one-terminal source is not a link
    if (e.schema && e.schema->observes) continue; // nor is a sensor of several nodes
    ids.clear();
    for (const int i : e.nodes)
      ids.push_back(i < 0 ? unknown : i);
    for (int id : ids) {
      comp.join(ids.front(), id);
      ++degree[static_cast<std::size_t>(id)];
    }
  }
  // The nodes by group (its root), in order: 8 bytes a node, a model may have millions.
  std::vector<std::pair<int, std::size_t>> by_group;
  std::set<int> grounded{comp.find(unknown)};
  for (std::size_t i = 0; i < n; ++i) {
    int root = comp.find(static_cast<int>(i));
    if (decls[i].boundary)
      grounded.insert(root);
    else
      by_group.emplace_back(root, i);
  }
  std::sort(by_group.begin(), by_group.end());
  // One warning per statement (a range, a loop or a submodel may declare millions of nodes),
  // naming the first few of its isolated nodes.
  std::vector<const ast::NodeStmt*> order;
  std::unordered_map<const ast::NodeStmt*, std::vector<std::size_t>> isolated;
  for (std::size_t i = 0; i < n; ++i) {
    if (decls[i].boundary || degree[i] != 0) continue;
    auto& members = isolated[decls[i].stmt];
    if (members.empty()) order.push_back(decls[i].stmt);
    members.push_back(i);
  }
  for (const ast::NodeStmt* stmt : order) {
    const auto& members = isolated[stmt];
    const NodeDecl& d = decls[members.front()];
    Diagnostic w =
        DiagnosticEngine::make(DiagId::isolated_node, start_of(d.where()), d.name_span(), d.name);
    if (members.size() > 1)
      w.message = fmt::format("nodes {} have no links", quoted_names(m, members));
    add_scope_notes(w, d.scope);
    report(std::move(w));
  }
  std::vector<std::size_t> members;
  for (std::size_t k = 0; k < by_group.size();) {
    const int root = by_group[k].first;
    members.clear();
    for (; k < by_group.size() && by_group[k].first == root; ++k)
      members.push_back(by_group[k].second);
    if (grounded.count(root) || members.size() < 2) continue;
    const NodeDecl& d = decls[members.front()];
    Diagnostic w = DiagnosticEngine::make(DiagId::floating_group, start_of(d.where()),
                                          d.name_span(), "nodes " + quoted_names(m, members));
    add_scope_notes(w, d.scope);
    report(std::move(w));
  }
}

} // namespace

Span ElementDecl::where() const {
  const ast::Tagged& s = element ? static_cast<const ast::Tagged&>(*element) : *composite;
  return Span{file, s.begin, s.end};
}

Span ElementDecl::name_span() const {
  const ast::Ref& n = element ? element->name : composite->name;
  return Span{file, n.begin, n.end};
}

void Model::lint(DiagnosticEngine& diags) const {
  // The base model is elaborated once per case; report each identical problem only once (and
  // none that loading reported already). A problem in a loop or an instance is reported once per
  // place, for the first iteration or instance where it arises.
  using Key = std::tuple<std::string, FileId, std::uint32_t, std::uint32_t, std::string>;
  std::set<Key> seen;
  auto key_of = [](const Diagnostic& d) {
    const Span at = d.at.value_or(Span{}), mark = d.mark.value_or(at);
    return Key{d.code, at.file, at.begin, d.generated ? mark.begin : 0u,
               d.generated ? std::string() : d.message};
  };
  for (const auto& d : diags.all())
    seen.insert(key_of(d));
  bool failed = false; // an error in the elaboration under way
  Reporter collect = [&](Diagnostic d) {
    if (d.severity == Severity::error) failed = true;
    if (seen.insert(key_of(d)).second) diags.add(std::move(d));
  };
  Elaborator base(*this, collect, nullptr, {}, true);
  NetworkSpec base_net = base.run();
  const bool base_failed = failed;
  for (const auto& v : values_) {
    try {
      base.value_of(v.name, v.name_span); // problems in unused declarations are problems too
    } catch (const EvalError&) {
    }
  }
  if (cases_.empty() && !failed && !load_error_) {
    base_net.settings.name = "default";
    remember("default", std::move(base_net));
  }
  // After a syntax error (or loops cut short) the model is incomplete: warnings about its shape and
  // about unused values could be caused by the statements that were skipped, so only errors are
  // reported.
  const bool complete = syntax_errors_ == 0 && !truncated_;
  if (complete) check_topology(*this, collect);
  check_sensor_names(*this, collect);
  std::set<std::string, std::less<>> used = base.used_names();
  used.insert(structurally_used_.begin(), structurally_used_.end());
  // A case that sets no param has the base model's nodes and elements (and their problems, all
  // reported by now): it takes the base network instead of elaborating them again.
  std::size_t reusing = 0;
  const bool own_networks = reads_case_data() || base.reads_keys();
  for (const auto& c : cases_)
    reusing += own_networks || Elaborator::sets_params(c) ? 0 : 1;
  for (const auto& c : cases_) {
    if (diags.saturated()) {
      diags.stop_early();
      return;
    }
    Elaborator ec(*this, collect, &c, {}, true);
    NetworkSpec net;
    if (own_networks || Elaborator::sets_params(c)) {
      failed = false;
      net = ec.run();
    } else {
      failed = base_failed;
      // The last case to take the base network takes it over; the others take a copy.
      net = ec.run_on(--reusing == 0 ? std::move(base_net) : base_net, base);
    }
    if (!failed && !load_error_) remember(c.name, std::move(net));
    used.insert(ec.used_names().begin(), ec.used_names().end());
  }
  for (const auto& v : values_)
    if (complete && !used.count(v.name))
      collect(DiagnosticEngine::make(v.is_param ? DiagId::unused_param : DiagId::unused_const,
                                     start_of(v.where), v.name_span, v.name));
}

bool Model::reads_case_data() const {
  for (const auto& f : files_)
    for (const auto& s : f->signals) {
      const auto* t = std::get_if<ast::TableSignal>(&s);
      if (!t) continue;
      if (t->case_data) return true;
      // A table of absolute times is placed on the case's clock (its data file's first row).
      CsvLayout layout;
      if (t->options.time && t->options.time->unit &&
          !parse_time_format(t->options.time->unit->text, layout) && layout.absolute())
        return true;
    }
  return false;
}

void Model::remember(const std::string& case_name, NetworkSpec net) const {
  std::lock_guard lock(cache_mutex_);
  cache_[case_name] = std::make_shared<NetworkSpec>(std::move(net));
}

std::shared_ptr<const NetworkSpec> Model::network(const std::string& case_name) const {
  const std::string name = resolve_case(case_name);
  {
    std::lock_guard lock(cache_mutex_);
    if (auto it = cache_.find(name); it != cache_.end()) return it->second;
  }
  auto net = std::make_shared<NetworkSpec>(instantiate(name));
  std::lock_guard lock(cache_mutex_);
  return cache_.emplace(name, std::move(net)).first->second;
}

NetworkSpec Model::take_network(const std::string& case_name) const {
  const std::string name = resolve_case(case_name);
  {
    std::lock_guard lock(cache_mutex_);
    if (auto it = cache_.find(name); it != cache_.end() && it->second.use_count() == 1) {
      NetworkSpec net = std::move(*it->second);
      cache_.erase(it);
      return net;
    }
  }
  return instantiate(name);
}

NetworkSpec Model::instantiate(const std::string& case_name, const ParamValues& params) const {
  return instantiate(case_name, params, overrides_);
}

NetworkSpec Model::instantiate(const std::string& case_name, const ParamValues& params,
                               const Overrides& overrides) const {
  std::string name = resolve_case(case_name);
  if (load_error_) throw ModelError(*load_error_);
  if (params.empty() && &overrides == &overrides_) { // the cache holds networks with overrides_
    std::lock_guard lock(cache_mutex_);
    if (auto it = cache_.find(name); it != cache_.end()) return *it->second;
  }
  return elaborate_near(name, nullptr, params, nullptr, overrides);
}

const CaseDecl* Model::find_case(std::string_view name) const {
  for (const auto& d : cases_)
    if (d.name == name) return &d;
  return nullptr;
}

NetworkSpec Model::instantiate_recorded(const std::string& case_name, const ParamValues& params,
                                        std::shared_ptr<const ElaborationRecord>& record) const {
  return elaborate_near(resolve_case(case_name), nullptr, params, &record, overrides_);
}

NetworkSpec Model::instantiate_near(const ElaborationRecord& from, const ParamValues& params,
                                    std::shared_ptr<const ElaborationRecord>* record) const {
  return elaborate_near(from.case_name, &from, params, record, overrides_);
}

NetworkSpec Model::elaborate_near(const std::string& name, const ElaborationRecord* from,
                                  const ParamValues& params,
                                  std::shared_ptr<const ElaborationRecord>* record,
                                  const Overrides& overrides) const {
  if (load_error_) throw ModelError(*load_error_);
  Reporter fail = [](Diagnostic d) {
    if (d.severity == Severity::error) throw ModelError(std::move(d));
  };
  const CaseDecl* c = find_case(name);
  Elaborator e(*this, fail, c, params, false, &overrides);
  // The model's params whose value differs (set on one side only, or to another value); others
  // (a case's start temperatures) are applied with the case's settings, which are elaborated anew.
  ParamReads moved;
  if (from) {
    const auto move = [&](const std::string& p) {
      if (const ValueDecl* d = e.value_decl(p)) moved.push_back(d);
    };
    for (const auto& [p, value] : params)
      if (auto it = from->params.find(p); it == from->params.end() || !(it->second == value))
        move(p);
    for (const auto& [p, value] : from->params)
      if (!params.count(p)) move(p);
  }
  std::optional<ElaborationRecord> r;
  NetworkSpec net = e.run_near(from, moved, record ? &r : nullptr);
  if (!c) net.settings.name = name;
  if (record) {
    record->reset();
    if (r) {
      r->case_name = name;
      r->params = params;
      *record = std::make_shared<const ElaborationRecord>(std::move(*r));
    }
  }
  return net;
}

std::vector<ParamInfo> Model::params() const {
  Reporter fail = [](Diagnostic d) {
    if (d.severity == Severity::error) throw ModelError(std::move(d));
  };
  Elaborator e(*this, fail, nullptr, {}, false);
  std::vector<ParamInfo> out;
  for (const auto& v : values_) {
    if (!v.is_param) continue;
    Quantity q;
    try {
      q = e.value_of(v.name, v.name_span);
    } catch (const EvalError& err) {
      throw ModelError(err.diag);
    }
    ParamInfo p;
    p.name = v.name;
    p.value = q.value;
    p.dim = q.dim;
    p.doc = v.doc;
    p.file = v.file;
    p.value_span = Span{v.file, v.expr->begin, v.expr->end};
    if (auto r = e.range_of(v.name)) {
      p.lo = r->first;
      p.hi = r->second;
    }
    out.push_back(std::move(p));
  }
  // Start temperatures calibrated per case (`w.T0 = 20 range 15 .. 30` in a case block).
  for (const auto& c : cases_) {
    Elaborator ec(*this, fail, &c, {}, false);
    for (const auto& item : c.stmt->items) {
      const auto* a = std::get_if<ast::CaseAssign>(&item);
      if (!a || !a->range || !a->value.as_expr()) continue;
      const ast::Ref& path = a->target.path;
      if (path.rest().empty() || path.rest().back().id.name != "T0") continue; // reported
      ParamInfo p;
      try {
        std::string node = ec.reference_text(path, c.file, nullptr);
        node.resize(node.size() - 3); // without ".T0"
        p.name = case_param_name(node, c.name);
        auto kelvin = [&](const ast::Expr& e) {
          const Quantity q = ec.evaluate(e, c.file, nullptr);
          return q.value + bare_temperature_offset(q, true);
        };
        p.value = kelvin(*a->value.as_expr());
        p.lo = kelvin(a->range->lo);
        p.hi = kelvin(a->range->hi);
      } catch (const EvalError& err) {
        throw ModelError(err.diag);
      }
      p.dim = dim::temperature;
      p.doc = fmt::format("start temperature of '{}' in case '{}'",
                          p.name.substr(0, p.name.find(".T0@")), c.name);
      p.file = c.file;
      p.value_span = Span{c.file, a->value.expr.begin, a->value.expr.end};
      p.case_name = c.name;
      out.push_back(std::move(p));
    }
  }
  return out;
}

} // namespace thermnet::lang
