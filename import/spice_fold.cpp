#include "import/spice_fold.hpp"

#include "import/spice_names.hpp"
#include "import/tnet_writer.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <set>

namespace thermnet::importer::spice {

namespace {

/// What an instance of a subcircuit looks like from outside, once its submodel is written.
struct Signature {
  std::string name;                   // the submodel's name
  std::vector<std::string> terminals; // thermnet names of its terminals (without gnd)
  bool gnd = false;                   // node 0 is used inside: a last terminal `gnd`
  std::vector<SubmodelParam> params;  // the params it declares
  std::vector<std::string> spice;     // their SPICE names
};

/// A scope being written: a submodel's body or the top level.
struct Body {
  std::vector<Boundary> boundaries;
  std::vector<Node> nodes;
  std::vector<Link> links;
  std::vector<Heater> heaters;
  std::vector<InstanceStmt> instances;
  std::set<std::string> words; // identifiers in the params' expressions written
  bool gnd = false;            // node 0 referred to
};

/// A node a scope cannot see: the instance it belongs to.
struct Invisible {
  std::size_t owner;
};

void identifiers(const std::string& text, std::set<std::string>& out) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (std::isalpha(c) || c == '_') {
      std::size_t j = i;
      while (j < text.size() &&
             (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_'))
        ++j;
      out.insert(text.substr(i, j - i));
      i = j;
    } else if (std::isdigit(c) || c == '.') {
      // a number, its exponent included (1e-05)
      std::size_t j = i;
      while (j < text.size() &&
             (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '.' ||
              ((text[j] == '-' || text[j] == '+') && j > i &&
               (text[j - 1] == 'e' || text[j - 1] == 'E'))))
        ++j;
      i = j;
    } else
      ++i;
  }
}

// Adds to `words` the names that the values of the `defs` it names use, and theirs, until none
// is added.
void add_used(const std::vector<SubcktParam>& defs, std::set<std::string>& words) {
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& d : defs)
      if (words.count(d.name) && d.text) {
        const std::size_t before = words.size();
        identifiers(*d.text, words);
        grew = grew || words.size() != before;
      }
  }
}

class Folder {
public:
  Folder(const Network& flat, const Circuit& c, const lang::SourceManager& sources,
         const std::function<bool(const std::string&)>& is_kind)
      : flat_(flat), c_(c), sources_(sources), is_kind_(is_kind) {}

  Folded run() {
    const std::size_t n = c_.instances.size();
    children_.assign(n, {});
    for (std::size_t k = 1; k < n; ++k) {
      children_[c_.instances[k].parent].push_back(k);
      of_subckt_[c_.instances[k].subckt].push_back(k);
    }
    index_items();
    order_subckts();
    for (const auto& [name, at] : c_.unused)
      notes_.emplace_back(at, fmt::format("subcircuit '{}' is never instantiated: not written",
                                          lang::excerpt_for_display(name)));
    // Each round writes the subcircuits innermost first; a node one cannot see flattens a
    // subcircuit and starts again (each round flattens one more, so this ends).
    for (;;) {
      if (auto net = attempt()) {
        for (const auto& [name, why] : why_flat_)
          notes_.emplace_back(
              c_.subckts.at(name).at,
              fmt::format("subcircuit '{}' is written flattened (its instances' names "
                          "joined by '_', e.g. x1_r1): {}",
                          lang::excerpt_for_display(name), why));
        for (const auto& sub : net->submodels)
          for (const auto& [spice, name] : sub_names_)
            if (name == sub.name && name != spice)
              notes_.emplace_back(sub.origin,
                                  fmt::format("subcircuit '{}' is written as submodel '{}' (a "
                                              "thermnet name, not a keyword or an element kind)",
                                              lang::excerpt_for_display(spice), name));
        for (const std::string& name : empty_)
          notes_.emplace_back(c_.subckts.at(name).at,
                              fmt::format("subcircuit '{}' keeps nothing of its own (what it "
                                          "holds acts on its terminals' nodes, where it is "
                                          "written): no submodel",
                                          lang::excerpt_for_display(name)));
        // Full names: an instance's prefix is its parent's and its own name.
        Folded out;
        out.prefix.assign(c_.instances.size(), "");
        for (std::size_t k = 1; k < c_.instances.size(); ++k) // (a parent precedes its children)
          if (auto it = inst_name_.find(k); it != inst_name_.end())
            out.prefix[k] = out.prefix[effective(c_.instances[k].parent)] + it->second + ".";
        out.local = std::move(local_);
        out.net = std::move(*net);
        out.notes = std::move(notes_);
        return out;
      }
    }
  }

private:
  void index_items() {
    const std::size_t n = c_.instances.size();
    b_at_.assign(n, {});
    n_at_.assign(n, {});
    l_at_.assign(n, {});
    h_at_.assign(n, {});
    for (std::size_t i = 0; i < flat_.boundaries.size(); ++i)
      b_at_[flat_.boundaries[i].scope].push_back(i);
    for (std::size_t i = 0; i < flat_.nodes.size(); ++i)
      n_at_[flat_.nodes[i].scope].push_back(i);
    for (std::size_t i = 0; i < flat_.links.size(); ++i)
      l_at_[flat_.links[i].scope].push_back(i);
    for (std::size_t i = 0; i < flat_.heaters.size(); ++i)
      h_at_[flat_.heaters[i].scope].push_back(i);
  }

  /// Subcircuits ordered so that each comes after those it instantiates.
  void order_subckts() {
    std::map<std::string, std::set<std::string>> uses;
    for (std::size_t k = 1; k < c_.instances.size(); ++k) {
      const Instance& in = c_.instances[k];
      uses[in.subckt];
      if (in.parent != 0) uses[c_.instances[in.parent].subckt].insert(in.subckt);
    }
    std::set<std::string> placed;
    while (placed.size() < uses.size()) {
      const std::size_t before = placed.size();
      for (const auto& [s, inner] : uses)
        if (!placed.count(s) && std::all_of(inner.begin(), inner.end(),
                                            [&](const auto& x) { return placed.count(x) > 0; })) {
          order_.push_back(s);
          placed.insert(s);
        }
      if (placed.size() == before) break; // (a cycle is reported before this runs)
    }
  }

  bool flat_subckt(std::size_t k) const {
    return k != 0 && why_flat_.count(c_.instances[k].subckt) > 0;
  }

  /// The instance whose scope holds what instance k holds.
  std::size_t effective(std::size_t k) const {
    while (flat_subckt(k))
      k = c_.instances[k].parent;
    return k;
  }

  /// The scopes written in instance i's body and the instances it states.
  void gather(std::size_t i, std::vector<std::size_t>& scopes, std::vector<std::size_t>& inst) {
    scopes.push_back(i);
    for (std::size_t k : children_[i])
      if (flat_subckt(k))
        gather(k, scopes, inst);
      else
        inst.push_back(k);
  }

  std::optional<Network> attempt() {
    sig_.clear();
    empty_.clear();
    local_.clear();
    inst_name_.clear();
    std::map<std::string, Submodel> written;
    for (const std::string& s : order_) {
      if (why_flat_.count(s)) continue;
      std::optional<std::string> first;
      std::string why;
      for (std::size_t k : of_subckt_[s]) {
        Body body;
        Signature sig;
        if (!render(k, body, sig)) return std::nullopt;
        Submodel sub = submodel(k, std::move(body), sig);
        std::string text = write_submodel(sub, sources_);
        if (!first) {
          first = std::move(text);
          sig_[s] = sig;
          written[s] = std::move(sub);
        } else if (text != *first)
          why = fmt::format("its instances {} and {} come out different (a value its "
                            "parameters cannot express, a Foster network converted to different "
                            "Cauer ladders, or node 0 on a terminal of one instance only)",
                            lang::excerpt_for_display(first_instance(s)),
                            lang::excerpt_for_display(c_.instances[k].prefix));
        if (!why.empty()) break;
      }
      if (!why.empty()) {
        // Flattened into its parents, which come later (its own parts are not affected).
        why_flat_[s] = why;
        written.erase(s);
        sig_.erase(s);
        continue;
      }
      // A part left with nothing of its own (its capacitors on its terminals, a V source holding
      // one) is neither written nor stated.
      const Submodel& w = written.at(s);
      if (w.boundaries.empty() && w.nodes.empty() && w.links.empty() && w.heaters.empty() &&
          w.instances.empty())
        empty_.insert(s);
    }
    Body top;
    Signature none;
    if (!render(0, top, none)) return std::nullopt;
    Network net;
    net.format = flat_.format;
    net.model = flat_.model;
    net.heading = flat_.heading;
    net.consts = flat_.consts;
    // The netlist's .param values the top level uses (and those they use), as consts.
    std::set<std::string> words = top.words;
    add_used(c_.globals, words);
    for (const auto& g : c_.globals)
      if (words.count(g.name) && g.text)
        net.consts.push_back({g.name, *g.text, place_text(sources_, g.at) + " .param"});
    net.case_spec = flat_.case_spec;
    net.boundaries = std::move(top.boundaries);
    net.nodes = std::move(top.nodes);
    net.links = std::move(top.links);
    net.heaters = std::move(top.heaters);
    net.instances = std::move(top.instances);
    for (const std::string& s : order_)
      if (auto it = written.find(s); it != written.end() && !why_flat_.count(s) && !empty_.count(s))
        net.submodels.push_back(std::move(it->second));
    if (!net.submodels.empty())
      net.expanded = Counts{flat_.nodes.size(), flat_.boundaries.size(), flat_.links.size(),
                            flat_.heaters.size()};
    return net;
  }

  std::string first_instance(const std::string& s) const {
    for (std::size_t k = 1; k < c_.instances.size(); ++k)
      if (c_.instances[k].subckt == s) return c_.instances[k].prefix;
    return s;
  }

  /// A unique thermnet name in `used` made of `wanted`.
  static std::string unique(const std::string& wanted, std::set<std::string>& used) {
    std::string name = wanted;
    for (int k = 2; !used.insert(name).second; ++k)
      name = fmt::format("{}_{}", wanted, k);
    return name;
  }

  std::string submodel_name(const std::string& spice) {
    if (auto it = sub_names_.find(spice); it != sub_names_.end()) return it->second;
    std::string name = sanitize(spice);
    static constexpr const char* reserved[] = {"for", "submodel", "in", "sensor", "data"};
    const auto bad = [&](const std::string& n) {
      return is_kind_(n) || std::any_of(std::begin(reserved), std::end(reserved),
                                        [&](const char* r) { return n == r; });
    };
    while (bad(name))
      name += "_";
    name = unique(name, used_sub_names_);
    return sub_names_[spice] = name;
  }

  /// Writes instance i's body (i = 0: the top level); false when a node it needs is out of its
  /// sight (a subcircuit was flattened: try again).
  bool render(std::size_t i, Body& body, Signature& sig) {
    std::vector<std::size_t> scopes, inst;
    gather(i, scopes, inst);
    const auto collect = [&](const std::vector<std::vector<std::size_t>>& at) {
      std::vector<std::size_t> out;
      for (std::size_t s : scopes)
        out.insert(out.end(), at[s].begin(), at[s].end());
      std::sort(out.begin(), out.end());
      return out;
    };
    const std::string prefix = i == 0 ? "" : c_.instances[i].prefix + ".";
    const auto rel = [&](const std::string& flat) {
      return flat.compare(0, prefix.size(), prefix) == 0 ? flat.substr(prefix.size()) : flat;
    };
    const auto relative_what = [&](std::string what) {
      if (prefix.empty()) return what;
      for (std::size_t p = what.find(prefix); p != std::string::npos; p = what.find(prefix, p))
        what.erase(p, prefix.size());
      return what;
    };
    std::set<std::string> node_names{"gnd"}, elem_names;
    if (i != 0) {
      const SubcktDef& def = c_.subckts.at(c_.instances[i].subckt);
      sig.name = submodel_name(def.name);
      for (const auto& t : def.terminals)
        sig.terminals.push_back(unique(sanitize(t), node_names));
    }
    std::optional<Invisible> invisible;
    const auto ref = [&](const std::string& flat) -> std::string {
      if (flat == "0") {
        body.gnd = true;
        return "gnd";
      }
      if (auto it = local_.find(flat); it != local_.end() && it->second.first == i)
        return it->second.second;
      if (i != 0) {
        const auto& b = c_.instances[i].bindings;
        for (std::size_t t = 0; t < b.size(); ++t)
          if (b[t] == flat) return sig.terminals[t];
      }
      auto s = c_.node_scope.find(flat);
      invisible = Invisible{effective(s == c_.node_scope.end() ? 0 : s->second)};
      return "?";
    };
    const auto value = [&](const Value& v, std::size_t scope) {
      if (scope == i && !v.scoped.empty()) {
        identifiers(v.scoped, body.words);
        return Value{v.scoped, v.si, ""};
      }
      return Value{v.text, v.si, ""};
    };
    const auto signal = [&](Signal s, std::size_t scope) {
      s.constant = value(s.constant, scope);
      for (auto& [t, v] : s.points) {
        t = value(t, scope);
        v = value(v, scope);
      }
      return s;
    };
    const auto what = [&](const std::string& flat, const std::string& name,
                          const std::string& extra, const char* sep) {
      std::string text =
          name != rel(flat) ? "SPICE node " + lang::excerpt_for_display(rel(flat), 60) : "";
      const std::string more = relative_what(extra);
      if (!more.empty()) text += (text.empty() ? "" : sep) + more;
      return text;
    };
    // Declarations: boundaries, then nodes (a Cauer ladder's nodes named after its driven node).
    std::map<std::string, std::string> ladder;
    // key: \x01 kind \x01 chain \x01 driven; the resistors' base is the nodes' base + "_r".
    const auto node_base = [&](const std::string& key) {
      const std::string nkey = std::string(key).replace(1, 1, "n");
      auto it = ladder.find(nkey);
      if (it != ladder.end()) return it->second;
      const std::string driven = key.substr(key.find('\x01', 3) + 1);
      const std::string base = unique("cauer_" + ref(driven), node_names);
      local_[nkey] = {i, base};
      return ladder[nkey] = base;
    };
    const auto ladder_base = [&](const std::string& key, std::set<std::string>& used,
                                 const char* suffix) {
      if (!*suffix) return node_base(key);
      auto it = ladder.find(key);
      if (it != ladder.end()) return it->second;
      return ladder[key] = unique(node_base(key) + suffix, used);
    };
    for (std::size_t k : collect(b_at_)) {
      Boundary b = flat_.boundaries[k];
      const std::string flat = b.name.base;
      const std::string name = flat == "0" ? "gnd" : unique(sanitize(rel(flat)), node_names);
      if (flat != "0") local_[flat] = {i, name};
      b.what = flat == "0" ? b.what : what(flat, name, b.what, ", ");
      b.name = Name{name, {}};
      b.T = signal(b.T, b.scope);
      body.boundaries.push_back(std::move(b));
    }
    for (std::size_t k : collect(n_at_)) {
      Node nd = flat_.nodes[k];
      if (nd.name.base[0] == '\x01') {
        nd.name.base = ladder_base(nd.name.base, node_names, "");
      } else {
        const std::string flat = nd.name.base;
        const std::string name = unique(sanitize(rel(flat)), node_names);
        local_[flat] = {i, name};
        nd.what = what(flat, name, nd.what, "; ");
        nd.name = Name{name, {}};
      }
      nd.C = value(nd.C, nd.scope);
      body.nodes.push_back(std::move(nd));
    }
    for (std::size_t k : collect(l_at_)) {
      Link l = flat_.links[k];
      if (l.name.base[0] == '\x01')
        l.name.base = ladder_base(l.name.base, elem_names, "_r");
      else
        l.name = Name{unique(sanitize(rel(l.name.base)), elem_names), {}};
      for (Name* t : {&l.a, &l.b})
        if (t->base[0] == '\x01')
          t->base = ladder_base(std::string(t->base), node_names, "");
        else
          *t = Name{ref(t->base), {}};
      l.value = value(l.value, l.scope);
      body.links.push_back(std::move(l));
    }
    for (std::size_t k : collect(h_at_)) {
      Heater h = flat_.heaters[k];
      h.name = Name{unique(sanitize(rel(h.name.base)), elem_names), {}};
      h.node = Name{ref(h.node.base), {}};
      h.P = signal(h.P, h.scope);
      body.heaters.push_back(std::move(h));
    }
    std::sort(inst.begin(), inst.end());
    for (std::size_t k : inst) {
      const Instance& in = c_.instances[k];
      if (empty_.count(in.subckt)) continue;
      const Signature& s = sig_.at(in.subckt);
      InstanceStmt st;
      st.submodel = s.name;
      st.name = unique(sanitize(rel(in.prefix)), elem_names);
      inst_name_[k] = st.name;
      if (st.name != rel(in.prefix))
        st.what = "SPICE " + lang::excerpt_for_display(rel(in.prefix), 60);
      st.origin = in.at;
      for (const auto& b : in.bindings)
        st.nodes.push_back(ref(b));
      if (s.gnd) st.nodes.push_back(ref("0"));
      for (std::size_t p = 0; p < s.params.size(); ++p) {
        const std::string& spice = s.spice[p];
        if (auto it = in.keys.find(spice); it != in.keys.end()) {
          const bool text = in.parent == i && it->second.first;
          if (text) identifiers(*it->second.first, body.words);
          st.keys.emplace_back(s.params[p].name,
                               text ? *it->second.first : number_text(it->second.second));
        } else if (!s.params[p].default_) {
          auto v = in.values.find(spice);
          if (v == in.values.end()) {
            why_flat_[in.subckt] = "a parameter without a value that thermnet can write";
            return false;
          }
          st.keys.emplace_back(s.params[p].name, number_text(v->second));
        }
      }
      body.instances.push_back(std::move(st));
    }
    if (invisible) {
      // A chain or element reaches a node of another part: flatten the part that holds it (or,
      // when that is an outer part, this one).
      std::size_t j = invisible->owner;
      bool inside = false;
      for (std::size_t s = j; s != 0; s = c_.instances[s].parent)
        if (s == i && j != i) inside = true;
      const std::size_t victim = inside ? j : i;
      if (victim == 0) return true; // (cannot happen: the top level sees every top node)
      why_flat_[c_.instances[victim].subckt] = "a Foster network or element crosses its boundary";
      return false;
    }
    return true;
  }

  Submodel submodel(std::size_t k, Body body, Signature& sig) {
    const Instance& in = c_.instances[k];
    const SubcktDef& def = c_.subckts.at(in.subckt);
    Submodel s;
    s.name = sig.name;
    s.terminals = sig.terminals;
    sig.gnd = body.gnd;
    if (body.gnd) s.terminals.push_back("gnd");
    // The consts used (and those they use), then the params used.
    std::set<std::string> words = body.words;
    add_used(def.locals, words);
    for (const auto& p : def.params)
      if (words.count(p.name)) {
        sig.params.push_back({p.name, p.needs_instance ? std::nullopt : p.text, p.at});
        sig.spice.push_back(p.spice);
      }
    s.params = sig.params;
    for (const auto& l : def.locals)
      if (words.count(l.name) && l.text)
        s.consts.push_back({l.name, *l.text, place_text(sources_, l.at) + " .param"});
    s.boundaries = std::move(body.boundaries);
    s.nodes = std::move(body.nodes);
    s.links = std::move(body.links);
    s.heaters = std::move(body.heaters);
    s.instances = std::move(body.instances);
    if (s.name != def.name) s.what = "SPICE subcircuit " + lang::excerpt_for_display(def.name, 60);
    s.origin = def.at;
    return s;
  }

  const Network& flat_;
  const Circuit& c_;
  const lang::SourceManager& sources_;
  const std::function<bool(const std::string&)>& is_kind_;
  std::vector<std::vector<std::size_t>> children_, b_at_, n_at_, l_at_, h_at_;
  std::vector<std::string> order_;
  std::map<std::string, std::vector<std::size_t>> of_subckt_; // subcircuit -> its instances
  std::map<std::string, std::string> why_flat_;
  std::map<std::string, Signature> sig_;
  std::set<std::string> empty_; // subcircuits with nothing of their own
  std::map<std::string, std::string> sub_names_;
  std::set<std::string> used_sub_names_;
  std::unordered_map<std::string, std::pair<std::size_t, std::string>>
      local_;                                    // flat -> scope, name
  std::map<std::size_t, std::string> inst_name_; // instance -> its name
  std::vector<std::pair<lang::Span, std::string>> notes_;
};

} // namespace

std::string Folded::name(const std::string& flat) const {
  if (flat == "0") return "gnd";
  auto it = local.find(flat);
  return it == local.end() ? flat : prefix[it->second.first] + it->second.second;
}

Folded fold(const Network& flat, const Circuit& c, const lang::SourceManager& sources,
            const std::function<bool(const std::string&)>& is_kind) {
  return Folder(flat, c, sources, is_kind).run();
}

} // namespace thermnet::importer::spice
