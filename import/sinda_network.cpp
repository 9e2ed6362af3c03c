#include "import/sinda_network.hpp"

#include "import/sinda_units.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <unordered_map>

namespace thermnet::importer::sinda {

namespace {

/// A node or conductor: its submodel's number and its id.
using Key = std::pair<std::size_t, std::int64_t>;

struct KeyHash {
  std::size_t operator()(const Key& k) const {
    return std::hash<std::int64_t>()(k.second) * 31 + k.first;
  }
};

/// Ordered by base, then index.
bool name_less(const Name& a, const Name& b) {
  if (a.base != b.base) return a.base < b.base;
  return a.index.value_or(0) < b.index.value_or(0);
}

/// Whether a comes before b in reading order.
bool before(lang::Span a, lang::Span b) {
  return a.file != b.file ? a.file < b.file : a.begin < b.begin;
}

class Builder {
public:
  Builder(const Deck& deck, Report& report) : deck_(deck), report_(report) {}

  Network build() {
    const ConductorCard* radiation = nullptr;
    for (const auto& c : deck_.conductors)
      if (c.radiation) {
        radiation = &c;
        break;
      }
    Units units(deck_, radiation, report_);
    net_.format = "SINDA/FLUINT";
    net_.model = deck_.files.empty() ? "deck" : model_name(deck_.files.front(), "deck");
    std::string files;
    for (const auto& f : deck_.files)
      files += (files.empty() ? "" : ", ") + lang::escape_for_display(f);
    net_.heading.push_back("SINDA/FLUINT deck imported by `thermnet import`: " + files);
    if (!deck_.title.empty())
      net_.heading.push_back("TITLE " + lang::escape_for_display(deck_.title));
    net_.heading.push_back(units.description());
    net_.heading.push_back("Names: node N of submodel SUB is SUB[N]; conductor N (radiation "
                           "conductor -N) of SUB is SUB_G[N]; the heat load on node N is SUB_Q[N]");
    if (report_.error_count() > 0) return std::move(net_);
    nodes(units);
    conductors(units);
    loads(units);
    check_builds();
    case_spec(units);
    net_.consts = units.consts();
    return std::move(net_);
  }

private:
  void nodes(const Units& units) {
    index_.reserve(deck_.nodes.size());
    for (const NodeCard& n : deck_.nodes) {
      auto [it, fresh] = index_.emplace(key(n.sub, n.id), &n);
      if (!fresh) {
        report_.error(n.at, "duplicate-name",
                      fmt::format("node {}.{} is defined twice", n.sub, n.id),
                      {{it->second->at, "first defined here"}});
        continue;
      }
      try {
        Name name{n.sub, n.id};
        if (n.boundary) {
          net_.boundaries.push_back({name, {units.temperature(n.T, n.T_at), {}}, "", n.at});
        } else {
          const bool arithmetic = n.C <= 0;
          net_.nodes.push_back(
              {name, units.capacity(arithmetic ? 0.0 : n.C), units.temperature(n.T, n.T_at),
               arithmetic ? fmt::format("arithmetic (C = {})", number_text(n.C)) : "", n.at});
        }
      } catch (const ImportError& e) {
        report_.error(e);
      }
    }
    const auto by_name = [](const auto& a, const auto& b) { return name_less(a.name, b.name); };
    std::stable_sort(net_.nodes.begin(), net_.nodes.end(), by_name);
    std::stable_sort(net_.boundaries.begin(), net_.boundaries.end(), by_name);
  }

  /// The node card a reference names, or an error at the reference.
  const NodeCard* resolve(const NodeRef& r) {
    auto it = index_.find(key(r.sub, r.id));
    if (it != index_.end()) return it->second;
    report_.error(r.at, "unknown-node",
                  fmt::format("node {}.{} is defined by no node data", r.sub, r.id));
    return nullptr;
  }

  void conductors(const Units& units) {
    std::unordered_map<Key, const ConductorCard*, KeyHash> seen;
    seen.reserve(deck_.conductors.size());
    for (const ConductorCard& c : deck_.conductors) {
      if (report_.saturated()) return;
      auto [it, fresh] = seen.emplace(key(c.sub, c.id), &c);
      if (!fresh) {
        report_.error(c.at, "duplicate-name",
                      fmt::format("conductor {} of submodel {} is defined twice", c.id, c.sub),
                      {{it->second->at, "first defined here"}});
        continue;
      }
      const NodeCard* a = resolve(c.a);
      const NodeCard* b = resolve(c.b);
      if (a == nullptr || b == nullptr) continue;
      if (a == b) {
        report_.error(c.at, "self-link",
                      fmt::format("conductor {} of submodel {} connects node {}.{} to itself", c.id,
                                  c.sub, a->sub, a->id));
        continue;
      }
      if (c.G < 0) {
        report_.error(c.G_at, "invalid-value",
                      fmt::format("conductor {} of submodel {} has a negative {} ({})", c.id, c.sub,
                                  c.radiation ? "G" : "conductance", number_text(c.G)));
        continue;
      }
      const std::string label =
          fmt::format("{}conductor {}{} of {}", c.radiation ? "radiation " : "",
                      c.radiation ? "-" : "", c.id, c.sub);
      if (c.G == 0) {
        report_.note(c.at, label + " has G = 0 and carries no heat: not written");
        continue;
      }
      if (a->boundary && b->boundary) {
        report_.note(c.at, label + " joins two boundary nodes and changes no temperature: not "
                                   "written");
        continue;
      }
      Link link;
      link.kind = c.radiation ? LinkKind::radiation : LinkKind::conductance;
      link.name = Name{c.sub + "_G", c.id};
      link.a = Name{a->sub, a->id};
      link.b = Name{b->sub, b->id};
      link.value = c.radiation ? units.radiation(c.G) : units.conductance(c.G);
      link.origin = c.at;
      net_.links.push_back(std::move(link));
    }
    std::stable_sort(net_.links.begin(), net_.links.end(),
                     [](const Link& x, const Link& y) { return name_less(x.name, y.name); });
  }

  void loads(const Units& units) {
    struct Load {
      const NodeCard* node;
      std::vector<double> terms;
      std::vector<lang::Span> origins;
    };
    std::vector<Load> order;
    std::unordered_map<const NodeCard*, std::size_t> at;
    for (const SourceCard& s : deck_.sources) {
      const NodeCard* n = resolve(s.node);
      if (n == nullptr) continue;
      if (n->boundary) {
        report_.note(s.at, fmt::format("the heat load on boundary node {}.{} changes no "
                                       "temperature (SINDA ignores it): not written",
                                       n->sub, n->id));
        continue;
      }
      auto [it, fresh] = at.emplace(n, order.size());
      if (fresh) order.push_back({n, {}, {}});
      order[it->second].terms.push_back(s.Q);
      order[it->second].origins.push_back(s.at);
    }
    for (const Load& l : order)
      net_.heaters.push_back({Name{l.node->sub + "_Q", l.node->id},
                              Name{l.node->sub, l.node->id},
                              {units.power(l.terms), {}},
                              "",
                              l.origins});
    std::stable_sort(net_.heaters.begin(), net_.heaters.end(),
                     [](const Heater& x, const Heater& y) { return name_less(x.name, y.name); });
  }

  void check_builds() {
    std::set<std::string> subs;
    for (const NodeCard& n : deck_.nodes)
      subs.insert(n.sub);
    for (const Build& b : deck_.builds) {
      if (b.subs.empty()) continue;
      std::string left_out;
      for (const auto& s : subs)
        if (std::find(b.subs.begin(), b.subs.end(), s) == b.subs.end())
          left_out += (left_out.empty() ? "" : ", ") + s;
      if (!left_out.empty())
        report_.dropped(b.at, fmt::format("this BUILD leaves out submodel(s) {}, which are "
                                          "imported all the same (remove them by hand)",
                                          left_out));
    }
  }

  void case_spec(const Units& units) {
    const Control& c = deck_.control;
    const bool steady_first =
        deck_.steady && (!deck_.transient || before(*deck_.steady, *deck_.transient));
    if (deck_.steady && !deck_.transient) {
      report_.note(*deck_.steady, "the deck's OPERATIONS solves a steady state only: run "
                                  "`thermnet simulate MODEL --steady`");
      return;
    }
    if (!c.timend) {
      if (deck_.transient)
        report_.note(*deck_.transient, "no TIMEND in CONTROL DATA: give the transient's "
                                       "duration with `thermnet simulate --duration`");
      return;
    }
    const double start = c.timeo ? c.timeo->value : 0.0;
    const double span = c.timend->value - start;
    if (!(span > 0)) {
      report_.error(c.timend->at, "invalid-value",
                    fmt::format("TIMEND ({}) must lie after TIMEO ({})",
                                number_text(c.timend->value), number_text(start)));
      return;
    }
    if (start != 0)
      report_.note(c.timeo->at, fmt::format("TIMEO = {}: thermnet's case starts at time 0 and "
                                            "lasts TIMEND - TIMEO",
                                            number_text(start)));
    CaseSpec cs;
    cs.name = "transient";
    cs.duration = units.time(span);
    cs.origin = c.timend->at;
    if (c.output) {
      if (c.output->value > 0 && span / c.output->value > max_output_rows) {
        cs.output = units.time(span / max_output_rows);
        report_.note(c.output->at,
                     fmt::format("OUTPUT = {} would write {:.0f} rows: the case writes {:.0f}",
                                 number_text(c.output->value), span / c.output->value,
                                 max_output_rows));
      } else if (c.output->value > 0 && c.output->value <= span)
        cs.output = units.time(c.output->value);
      else
        report_.note(c.output->at, "OUTPUT is not an interval within the run: thermnet's "
                                   "default output interval is used");
    }
    if (steady_first) cs.initial = "steady";
    net_.case_spec = std::move(cs);
  }

  const Deck& deck_;
  Report& report_;
  Network net_;
  /// The key of a submodel's node or conductor (submodels numbered as first seen).
  Key key(const std::string& sub, std::int64_t id) {
    auto [it, fresh] = subs_.emplace(sub, subs_.size());
    return {it->second, id};
  }

  std::unordered_map<std::string, std::size_t> subs_;
  std::unordered_map<Key, const NodeCard*, KeyHash> index_;
};

} // namespace

Network deck_network(const Deck& deck, Report& report) {
  return Builder(deck, report).build();
}

} // namespace thermnet::importer::sinda
