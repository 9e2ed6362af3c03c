#include "import/spice_circuit.hpp"

#include "import/network.hpp"
#include "import/spice_expression.hpp"
#include "import/spice_names.hpp"
#include "import/spice_number.hpp"
#include "import/spice_params.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <memory>
#include <set>

namespace thermnet::importer::spice {

namespace {

/// How deep subcircuit instances may nest.
constexpr std::size_t max_instance_depth = 64;

struct Subckt {
  std::string name;
  std::vector<std::string> terminals;
  std::vector<std::pair<std::string, ParamDef>> defaults;
  std::vector<const Card*> cards;
  lang::Span at;
};

bool is_ground(const std::string& node) {
  return node == "0" || node == "gnd";
}

std::string kind_name(char c) {
  switch (c) {
  case 'l':
    return "an inductor";
  case 'e':
  case 'f':
  case 'g':
  case 'h':
    return "a controlled source";
  case 'b':
    return "a behavioural source";
  case 'd':
    return "a diode";
  case 'q':
  case 'm':
  case 'j':
  case 'z':
    return "a transistor";
  case 's':
  case 'w':
    return "a switch";
  case 't':
  case 'o':
  case 'u':
    return "a transmission line";
  case 'k':
    return "a coupling";
  case 'a':
    return "an XSPICE model";
  default:
    return "an element";
  }
}

class Flattener {
public:
  Flattener(Netlist& netlist, const lang::SourceManager& sources, Report& report)
      : net_(netlist), sources_(sources), report_(report), global_(nullptr) {}

  Circuit run() {
    circuit_.title = net_.title;
    circuit_.files = net_.files;
    std::vector<const Card*> top;
    split(top);
    for (const Card* c : top)
      if (lower(c->tokens[0].text) == ".param") guarded([&] { params(*c, global_, true); });
    describe_globals();
    std::vector<std::string> stack;
    circuit_.instances.push_back(Instance{});
    expand(top, global_, "", {}, 0, stack, true);
    for (const auto& [name, s] : subckts_)
      if (!circuit_.subckts.count(name)) circuit_.unused.emplace_back(name, s->at);
    return std::move(circuit_);
  }

private:
  template <typename F> void guarded(F&& f) {
    try {
      f();
    } catch (const ImportError& e) {
      report_.error(e);
    }
  }

  /// Sorts the cards into the top level and subcircuit definitions; skips .control blocks.
  void split(std::vector<const Card*>& top) {
    std::vector<Subckt*> open;
    bool control = false;
    lang::Span control_at;
    for (const Card& card : net_.cards) {
      const std::string head = lower(card.tokens[0].text);
      if (control) {
        if (head == ".endc") control = false;
        continue;
      }
      if (head == ".control") {
        control = true;
        control_at = card.at;
        report_.note(card.at, "ignored: the .control block (ngspice commands, which change no "
                              "temperature)");
        continue;
      }
      if (head == ".subckt") {
        guarded([&] { open.push_back(define(card)); });
        continue;
      }
      if (head == ".ends") {
        if (open.empty())
          report_.error(card.at, "bad-syntax", ".ends without .subckt");
        else
          open.pop_back();
        continue;
      }
      if (open.empty())
        top.push_back(&card);
      else
        open.back()->cards.push_back(&card);
    }
    if (control) report_.error(control_at, "bad-syntax", ".control without .endc");
    for (const Subckt* s : open)
      report_.error(s->at, "bad-syntax",
                    fmt::format(".subckt {} has no .ends", lang::excerpt_for_display(s->name)));
  }

  Subckt* define(const Card& card) {
    const auto& t = card.tokens;
    if (t.size() < 2 || t[1].kind != Token::Kind::word)
      throw ImportError(card.at, "bad-syntax", ".subckt needs a name: .subckt NAME NODE ...");
    auto s = std::make_unique<Subckt>();
    s->name = lower(t[1].text);
    s->at = card.at;
    std::size_t i = 2;
    for (; i < t.size(); ++i) {
      if (lower(t[i].text) == "params:") {
        ++i;
        break;
      }
      if (i + 1 < t.size() && t[i + 1].kind == Token::Kind::equals) break;
      if (t[i].kind != Token::Kind::word)
        throw ImportError(t[i].at, "bad-syntax", "expected a node name");
      s->terminals.push_back(lower(t[i].text));
    }
    read_assignments(sources_, t, i, s->defaults);
    auto [it, fresh] = subckts_.emplace(s->name, std::move(s));
    if (!fresh)
      throw ImportError(
          card.at, "duplicate-name",
          fmt::format("subcircuit '{}' is defined twice", lang::excerpt_for_display(it->first)));
    return it->second.get();
  }

  void params(const Card& c, ParamScope& scope, bool global = false) {
    std::vector<std::pair<std::string, ParamDef>> list;
    read_assignments(sources_, c.tokens, 1, list);
    for (auto& [name, def] : list) {
      scope.define(name, def);
      if (global) global_defs_.emplace_back(name, def);
    }
  }

  /// The netlist's .param values as the model's consts: thermnet names, and their expressions
  /// translated in rounds (one may use another that stands after it).
  void describe_globals() {
    std::set<std::string> used;
    for (const auto& [name, def] : global_defs_)
      circuit_.globals.push_back({name, param_name(name, used), std::nullopt, false, def.at});
    const NameText names = [&](const std::string& n) -> std::optional<std::string> {
      for (const auto& p : circuit_.globals)
        if (p.spice == n) return p.text ? std::optional<std::string>(p.name) : std::nullopt;
      return std::nullopt;
    };
    for (bool more = true; more;) {
      more = false;
      for (std::size_t j = 0; j < circuit_.globals.size(); ++j)
        if (!circuit_.globals[j].text) {
          circuit_.globals[j].text = translate(global_defs_[j].second.text, names);
          more = more || circuit_.globals[j].text.has_value();
        }
    }
  }

  /// A thermnet name for a parameter, unique in `used`: names thermnet gives meaning to inside
  /// an expression cannot name a param or const.
  static std::string param_name(const std::string& spice, std::set<std::string>& used) {
    static constexpr const char* taken[] = {
        "time",  "step", "pwl", "table", "data", "range", "in",  "for", "sqrt",   "exp",     "log",
        "log10", "sin",  "cos", "tan",   "abs",  "min",   "max", "pow", "steady", "submodel"};
    std::string base = sanitize(spice);
    for (const char* w : taken)
      if (base == w) base += "_";
    std::string n = base;
    for (int k = 2; !used.insert(n).second; ++k)
      n = fmt::format("{}_{}", base, k);
    return n;
  }

  struct Context {
    std::string prefix;
    std::map<std::string, std::string> nodes; // terminal -> outer node
    std::size_t scope = 0;                    // the instance
  };

  /// How a name stands in thermnet text in instance `scope`: a parameter or .param of its
  /// subcircuit by its thermnet name, a netlist's .param by its value.
  NameText names_in(std::size_t scope) const {
    const SubcktDef* def =
        scope == 0 ? nullptr : &circuit_.subckts.at(circuit_.instances[scope].subckt);
    return [this, def](const std::string& n) { return name_text(def, n); };
  }

  /// How a name stands in thermnet text inside subcircuit `def` (nullptr: at the top level).
  std::optional<std::string> name_text(const SubcktDef* def, const std::string& n) const {
    if (def != nullptr) {
      for (const auto& p : def->params)
        if (p.spice == n) return p.name;
      for (const auto& p : def->locals)
        if (p.spice == n) return p.text ? std::optional<std::string>(p.name) : std::nullopt;
    } else {
      // (at the top level a .param is a const of the model; inside a submodel its value)
      for (const auto& p : circuit_.globals)
        if (p.spice == n) return p.text ? std::optional<std::string>(p.name) : std::nullopt;
    }
    try {
      if (auto v = global_.lookup(n)) return number_text(*v);
    } catch (const ImportError&) {
    }
    return std::nullopt;
  }

  /// A value token as thermnet text in instance `scope`.
  /// A value token as thermnet text in instance `scope`; nothing for a plain number (the
  /// writer writes the value) and for what has no thermnet text. `number` gives a plain number
  /// its text instead.
  std::optional<std::string> text_of(const Token& t, std::size_t scope, bool number = false) const {
    if (t.kind == Token::Kind::expression) return translate(t.text, names_in(scope));
    if (t.kind != Token::Kind::word) return std::nullopt;
    if (auto n = spice_number(t.text))
      return number ? std::optional<std::string>(number_text(n->value)) : std::nullopt;
    return names_in(scope)(lower(t.text));
  }

  /// The description of a subcircuit for its submodel (made at its first instance).
  const SubcktDef& describe(const Subckt& s);

  std::string node(const Token& t, const Context& ctx) {
    if (t.kind != Token::Kind::word)
      throw ImportError(
          t.at, "bad-syntax",
          fmt::format("expected a node, found '{}'", lang::excerpt_for_display(t.text)));
    const std::string n = lower(t.text);
    if (is_ground(n)) return "0";
    if (auto it = ctx.nodes.find(n); it != ctx.nodes.end()) return it->second;
    if (ctx.prefix.empty()) return n;
    std::string flat = ctx.prefix + "." + n;
    circuit_.node_scope.emplace(flat, ctx.scope);
    return flat;
  }

  void expand(const std::vector<const Card*>& cards, const ParamScope& scope,
              const std::string& prefix, const std::map<std::string, std::string>& terminals,
              std::size_t instance, std::vector<std::string>& stack, bool top) {
    const Context ctx{prefix, terminals, instance};
    for (const Card* c : cards) {
      if (report_.saturated() || too_large_) return;
      guarded([&] { card(*c, scope, ctx, stack, top); });
    }
  }

  void card(const Card& c, const ParamScope& scope, const Context& ctx,
            std::vector<std::string>& stack, bool top) {
    const std::string head = lower(c.tokens[0].text);
    if (head[0] == '.') {
      directive(c, head, scope, ctx, top);
      return;
    }
    const char kind = head[0];
    const std::string flat = ctx.prefix.empty() ? head : ctx.prefix + "." + head;
    if (!names_.insert(flat).second)
      throw ImportError(c.tokens[0].at, "duplicate-name",
                        fmt::format("'{}' is defined twice", lang::excerpt_for_display(flat)));
    if (kind == 'x') {
      instance(c, scope, ctx, stack);
      return;
    }
    if (kind != 'r' && kind != 'c' && kind != 'i' && kind != 'v') {
      report_.dropped(c.at,
                      fmt::format("{} ('{}'): thermnet reads R, C, I, V and X cards",
                                  kind_name(kind), lang::excerpt_for_display(c.tokens[0].text)));
      return;
    }
    if (circuit_.elements.size() >= max_elements) {
      too_large_ = true;
      throw ImportError(c.at, "too-large",
                        fmt::format("the netlist expands to more than {} elements", max_elements));
    }
    element(c, kind, scope, ctx);
  }

  void element(const Card& c, char kind, const ParamScope& scope, const Context& ctx);
  void source_spec(const Card& c, Element& e, const ParamScope& scope);
  void instance(const Card& c, const ParamScope& scope, const Context& ctx,
                std::vector<std::string>& stack);
  void directive(const Card& c, const std::string& head, const ParamScope& scope,
                 const Context& ctx, bool top);

  Netlist& net_;
  const lang::SourceManager& sources_;
  Report& report_;
  ParamScope global_;
  std::map<std::string, std::unique_ptr<Subckt>> subckts_;
  std::vector<std::unique_ptr<ParamScope>> scopes_;
  std::set<std::string> names_; // flattened element and instance names
  std::vector<std::pair<std::string, ParamDef>> global_defs_; // the netlist's .param values
  Circuit circuit_;
  bool too_large_ = false;
};

void Flattener::element(const Card& c, char kind, const ParamScope& scope, const Context& ctx) {
  const auto& t = c.tokens;
  if (t.size() < 4)
    throw ImportError(c.at, "bad-syntax",
                      fmt::format("{} needs a name, two nodes and a value",
                                  lang::excerpt_for_display(t[0].text)));
  Element e;
  e.kind = kind;
  e.name = ctx.prefix.empty() ? lower(t[0].text) : ctx.prefix + "." + lower(t[0].text);
  e.a = node(t[1], ctx);
  e.b = node(t[2], ctx);
  e.at = c.at;
  e.scope = ctx.scope;
  if (kind == 'i' || kind == 'v') {
    source_spec(c, e, scope);
    circuit_.elements.push_back(std::move(e));
    return;
  }
  std::size_t i = 3;
  // `R1 a b 10`, or `R1 a b r = 10`.
  const char key = kind;
  if (i + 2 < t.size() && t[i].kind == Token::Kind::word && t[i + 1].kind == Token::Kind::equals &&
      lower(t[i].text) == std::string(1, key))
    i += 2;
  bool femto = false;
  e.value = scope.value(t[i], &femto);
  e.value_at = t[i].at;
  e.expr = text_of(t[i], ctx.scope);
  if (femto && kind == 'c')
    report_.note(t[i].at, fmt::format("'{}' reads as {} F: SPICE's suffix f is femto (1e-15), "
                                      "not farad",
                                      lang::excerpt_for_display(t[i].text), e.value));
  std::vector<std::pair<std::string, ParamDef>> extra;
  read_assignments(sources_, t, i + 1, extra);
  for (const auto& [name, def] : extra) {
    if (name == "m") {
      const double m = scope.evaluate(def);
      if (!(m > 0)) throw ImportError(def.at, "invalid-value", "the multiplier m must be positive");
      e.value = kind == 'r' ? e.value / m : e.value * m;
      e.expr.reset();
    } else if (kind == 'c' && name == "ic") {
      e.ic = scope.evaluate(def);
    } else {
      report_.dropped(def.at, fmt::format("the parameter '{}' of {} (its nominal value is written)",
                                          lang::excerpt_for_display(name),
                                          lang::excerpt_for_display(t[0].text)));
    }
  }
  circuit_.elements.push_back(std::move(e));
}

void Flattener::source_spec(const Card& c, Element& e, const ParamScope& scope) {
  const auto& t = c.tokens;
  bool have_dc = false;
  std::size_t i = 3;
  while (i < t.size()) {
    const std::string w = t[i].kind == Token::Kind::word ? lower(t[i].text) : "";
    if (w == "dc") {
      if (i + 1 >= t.size()) throw ImportError(t[i].at, "bad-syntax", "DC needs a value");
      std::size_t v = i + 1;
      if (t[v].kind == Token::Kind::equals) ++v;
      if (v >= t.size()) throw ImportError(t[i].at, "bad-syntax", "DC needs a value");
      e.value = scope.value(t[v]);
      e.value_at = t[v].at;
      e.expr = text_of(t[v], e.scope);
      have_dc = true;
      i = v + 1;
    } else if (w == "ac") {
      // AC magnitude and phase: small-signal analyses only.
      ++i;
      for (int k = 0; k < 2 && i < t.size() && t[i].kind != Token::Kind::open; ++k) {
        const std::string n = lower(t[i].text);
        if (n == "dc" || n == "pwl" ||
            !(t[i].kind == Token::Kind::expression || spice_number(t[i].text) || scope.lookup(n)))
          break;
        ++i;
      }
    } else if (w == "pwl") {
      if (i + 1 >= t.size() || t[i + 1].kind != Token::Kind::open)
        throw ImportError(t[i].at, "bad-syntax",
                          "PWL needs its points in parentheses: PWL(t1 v1 t2 v2 ...)");
      std::size_t j = i + 2;
      std::vector<const Token*> values;
      while (j < t.size() && t[j].kind != Token::Kind::close)
        values.push_back(&t[j++]);
      if (j >= t.size()) throw ImportError(t[i].at, "bad-syntax", "PWL( without its ')'");
      if (values.empty() || values.size() % 2 != 0)
        throw ImportError(t[i].at, "bad-syntax", "PWL needs pairs of time and value");
      for (std::size_t k = 0; k < values.size(); k += 2) {
        const double time = scope.value(*values[k]);
        if (!e.pwl.empty() && !(time > e.pwl.back().first))
          throw ImportError(values[k]->at, "invalid-value", "PWL times must increase");
        if (time < 0)
          throw ImportError(values[k]->at, "invalid-value", "a PWL time may not be negative");
        e.pwl.emplace_back(time, scope.value(*values[k + 1]));
        auto tt = text_of(*values[k], e.scope, true), vt = text_of(*values[k + 1], e.scope, true);
        if (tt && vt && e.pwl_expr.size() + 1 == e.pwl.size()) e.pwl_expr.emplace_back(*tt, *vt);
      }
      e.value_at = t[i].at;
      e.expr.reset();
      if (e.pwl_expr.size() != e.pwl.size()) e.pwl_expr.clear();
      i = j + 1;
      if (i < t.size()) {
        report_.dropped(t[i].at, fmt::format("the PWL options of {} (r=, td=: repetition and "
                                             "delay)",
                                             lang::excerpt_for_display(t[0].text)));
        return;
      }
    } else if (w == "pulse" || w == "sin" || w == "exp" || w == "sffm" || w == "am" ||
               w == "trnoise" || w == "trrandom" || w == "pat") {
      report_.dropped(t[i].at, fmt::format("the {} waveform of {} (thermnet reads DC and PWL "
                                           "sources; the DC value is written)",
                                           lang::excerpt_for_display(w),
                                           lang::excerpt_for_display(t[0].text)));
      return;
    } else if (!have_dc && e.pwl.empty()) {
      e.value = scope.value(t[i]);
      e.value_at = t[i].at;
      e.expr = text_of(t[i], e.scope);
      have_dc = true;
      ++i;
    } else {
      throw ImportError(
          t[i].at, "bad-syntax",
          fmt::format("unexpected '{}' in the source", lang::excerpt_for_display(t[i].text)));
    }
  }
  if (!have_dc && e.pwl.empty()) e.value_at = c.at; // no value: 0, as in SPICE
  if (have_dc && !e.pwl.empty() && e.value != e.pwl.front().second)
    report_.note(c.at, fmt::format("{}: the DC value is not written; the PWL gives the value at "
                                   "every time",
                                   lang::excerpt_for_display(t[0].text)));
}

void Flattener::instance(const Card& c, const ParamScope& scope, const Context& ctx,
                         std::vector<std::string>& stack) {
  const auto& t = c.tokens;
  std::size_t end = t.size(); // first token of the parameters
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (lower(t[i].text) == "params:" ||
        (i + 1 < t.size() && t[i + 1].kind == Token::Kind::equals)) {
      end = i;
      break;
    }
  }
  if (end < 3)
    throw ImportError(c.at, "bad-syntax", "an X card needs nodes and a subcircuit: X1 N1 N2 NAME");
  const Token& sub = t[end - 1];
  const std::string name = lower(sub.text);
  auto it = subckts_.find(name);
  if (it == subckts_.end())
    throw ImportError(
        sub.at, "unknown-subckt",
        fmt::format("no subcircuit is called '{}'", lang::excerpt_for_display(sub.text)));
  const Subckt& s = *it->second;
  if (end - 2 != s.terminals.size())
    throw ImportError(c.at, "bad-syntax",
                      fmt::format("subcircuit '{}' has {} node{}, the instance gives {}",
                                  lang::excerpt_for_display(name), s.terminals.size(),
                                  s.terminals.size() == 1 ? "" : "s", end - 2));
  if (std::find(stack.begin(), stack.end(), name) != stack.end())
    throw ImportError(
        c.at, "subckt-cycle",
        fmt::format("subcircuit '{}' contains itself", lang::excerpt_for_display(name)));
  if (stack.size() >= max_instance_depth)
    throw ImportError(
        c.at, "subckt-too-deep",
        fmt::format("subcircuit instances nest more than {} deep", max_instance_depth));
  std::map<std::string, std::string> terminals;
  for (std::size_t k = 0; k < s.terminals.size(); ++k)
    terminals[s.terminals[k]] = node(t[1 + k], ctx);
  auto inner = std::make_unique<ParamScope>(&global_);
  std::size_t from = end;
  if (from < t.size() && lower(t[from].text) == "params:") ++from;
  std::vector<std::pair<std::string, ParamDef>> given;
  read_assignments(sources_, t, from, given);
  const SubcktDef& def = describe(s);
  Instance inst;
  inst.name = lower(t[0].text);
  inst.subckt = name;
  inst.parent = ctx.scope;
  inst.at = c.at;
  for (const auto& term : s.terminals)
    inst.bindings.push_back(terminals.at(term));
  for (const auto& [pname, pdef] : given) {
    if (std::none_of(s.defaults.begin(), s.defaults.end(),
                     [&](const auto& d) { return d.first == pname; })) {
      std::string known;
      for (const auto& d : s.defaults)
        known += (known.empty() ? "" : ", ") + d.first;
      throw ImportError(pdef.at, "unknown-param",
                        fmt::format("subcircuit '{}' has no parameter '{}' ({})",
                                    lang::excerpt_for_display(name),
                                    lang::excerpt_for_display(pname),
                                    known.empty() ? "it has none" : "its parameters: " + known));
    }
    const double v = scope.evaluate(pdef);
    inner->set(pname, v);
    inst.keys[pname] = {translate(pdef.text, names_in(ctx.scope)), v};
  }
  for (const auto& [pname, pdef] : s.defaults)
    if (!inner->lookup_here(pname)) inner->define(pname, pdef);
  for (const Card* card : s.cards)
    if (lower(card->tokens[0].text) == ".param") params(*card, *inner);
  for (const auto& p : def.params)
    guarded([&] {
      if (auto v = inner->lookup(p.spice)) inst.values[p.spice] = *v;
    });
  inst.prefix = ctx.prefix.empty() ? inst.name : ctx.prefix + "." + inst.name;
  const std::string prefix = inst.prefix;
  const std::size_t index = circuit_.instances.size();
  circuit_.instances.push_back(std::move(inst));
  stack.push_back(name);
  expand(s.cards, *inner, prefix, terminals, index, stack, false);
  stack.pop_back();
  scopes_.push_back(std::move(inner));
}

const SubcktDef& Flattener::describe(const Subckt& s) {
  if (auto it = circuit_.subckts.find(s.name); it != circuit_.subckts.end()) return it->second;
  SubcktDef& d = circuit_.subckts[s.name];
  d.name = s.name;
  d.terminals = s.terminals;
  d.at = s.at;
  std::set<std::string> used;
  const auto name_of = [&](const std::string& spice) { return param_name(spice, used); };
  for (const auto& [pname, pdef] : s.defaults)
    d.params.push_back({pname, name_of(pname), std::nullopt, false, pdef.at});
  std::vector<ParamDef> local_defs; // (in the order of d.locals)
  for (const Card* card : s.cards) {
    if (lower(card->tokens[0].text) != ".param") continue;
    std::vector<std::pair<std::string, ParamDef>> list;
    try {
      read_assignments(sources_, card->tokens, 1, list);
    } catch (const ImportError&) {
      continue; // reported where the instance reads it
    }
    for (auto& [pname, pdef] : list) {
      d.locals.push_back({pname, name_of(pname), std::nullopt, false, pdef.at});
      local_defs.push_back(pdef);
    }
  }
  // Translations, now that every name is known; a default that uses the subcircuit's own names
  // cannot stand on the param line: every instance gives that value.
  std::size_t k = 0;
  for (const auto& [pname, pdef] : s.defaults) {
    bool own = false;
    d.params[k].text =
        translate(pdef.text, [&](const std::string& n) -> std::optional<std::string> {
          for (const auto& p : d.params)
            if (p.spice == n) own = true;
          for (const auto& p : d.locals)
            if (p.spice == n) own = true;
          if (own) return "0";
          try {
            if (auto v = global_.lookup(n)) return number_text(*v);
          } catch (const ImportError&) {
          }
          return std::nullopt;
        });
    if (own) {
      d.params[k].text.reset();
      d.params[k].needs_instance = true;
    }
    ++k;
  }
  // A .param may use another that stands after it: translated in rounds, each using those
  // translated before (one that uses a value thermnet cannot write stays untranslated).
  const NameText names = [&](const std::string& n) { return name_text(&d, n); };
  for (bool more = true; more;) {
    more = false;
    for (std::size_t j = 0; j < d.locals.size(); ++j)
      if (!d.locals[j].text) {
        d.locals[j].text = translate(local_defs[j].text, names);
        more = more || d.locals[j].text.has_value();
      }
  }
  return d;
}

void Flattener::directive(const Card& c, const std::string& head, const ParamScope& scope,
                          const Context&, bool top) {
  const auto& t = c.tokens;
  if (head == ".param") return; // read before the cards are expanded
  const auto top_only = [&] {
    if (!top)
      throw ImportError(c.at, "bad-syntax", fmt::format("{} stands outside subcircuits", head));
  };
  if (head == ".tran") {
    top_only();
    Tran tr;
    tr.at = c.at;
    std::vector<double> v;
    for (std::size_t i = 1; i < t.size(); ++i) {
      if (lower(t[i].text) == "uic") {
        tr.uic = true;
        continue;
      }
      v.push_back(scope.value(t[i]));
    }
    if (v.size() < 2 || v.size() > 4)
      throw ImportError(c.at, "bad-syntax", ".tran needs TSTEP TSTOP [TSTART [TMAX]] [UIC]");
    tr.step = v[0];
    tr.stop = v[1];
    tr.start = v.size() > 2 ? v[2] : 0.0;
    if (!(tr.stop > 0)) throw ImportError(t[2].at, "invalid-value", "TSTOP must be positive");
    if (!(tr.step > 0)) throw ImportError(t[1].at, "invalid-value", "TSTEP must be positive");
    if (circuit_.tran) throw ImportError(c.at, "duplicate-name", "a second .tran");
    circuit_.tran = tr;
    return;
  }
  if (head == ".ic") {
    top_only();
    // V(node) = value ...
    for (std::size_t i = 1; i < t.size();) {
      if (i + 5 > t.size() || lower(t[i].text) != "v" || t[i + 1].kind != Token::Kind::open ||
          t[i + 3].kind != Token::Kind::close || t[i + 4].kind != Token::Kind::equals)
        throw ImportError(t[i].at, "bad-syntax", ".ic takes V(NODE) = VALUE ...");
      if (i + 5 >= t.size()) throw ImportError(t[i].at, "bad-syntax", ".ic V(NODE) needs = VALUE");
      circuit_.ics.push_back({node(t[i + 2], Context{}), scope.value(t[i + 5]), t[i].at});
      i += 6;
    }
    return;
  }
  if (head == ".op") {
    if (!circuit_.op) circuit_.op = c.at;
    return;
  }
  static constexpr const char* output[] = {".print",   ".plot",  ".probe", ".save",    ".meas",
                                           ".measure", ".width", ".four",  ".options", ".option",
                                           ".opt",     ".temp",  ".model", ".nodeset", ".title"};
  for (const char* o : output)
    if (head == o) {
      report_.note(c.at, fmt::format("ignored: {} (changes no temperature)", head));
      return;
    }
  static constexpr const char* analyses[] = {".ac", ".dc",    ".noise", ".tf", ".sens",
                                             ".pz", ".disto", ".sp",    ".pss"};
  for (const char* a : analyses)
    if (head == a) {
      report_.note(c.at, fmt::format("ignored: the {} analysis (thermnet runs transients and "
                                     "steady states)",
                                     head));
      return;
    }
  report_.dropped(c.at, fmt::format("the {} statement", lang::excerpt_for_display(head)));
}

} // namespace

Circuit flatten(Netlist netlist, const lang::SourceManager& sources, Report& report) {
  return Flattener(netlist, sources, report).run();
}

} // namespace thermnet::importer::spice
