#include "import/tnet_writer.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

namespace thermnet::importer {

namespace {

/// Shortest runs worth a range or a loop.
constexpr std::size_t min_node_run = 2;
constexpr std::size_t min_loop_run = 3;

class Writer {
public:
  Writer(const lang::SourceManager& sources) : sources_(sources) {}

  std::string text() { return std::move(out_); }

  std::string write(const Network& net, const std::vector<Remark>& remarks) {
    for (const auto& h : net.heading)
      out_ += "# " + lang::escape_for_display(h) + "\n";
    for (const auto& r : remarks) {
      const std::string where = r.at ? place_text(sources_, *r.at) + ": " : "";
      out_ += fmt::format("# {}: {}{}\n", r.dropped ? "not translated" : "note", where,
                          lang::escape_for_display(r.text));
    }
    out_ += "\nmodel " + net.model + "\n";
    if (!net.consts.empty()) out_ += "\n";
    for (const auto& c : net.consts)
      out_ +=
          fmt::format("const {} = {}  # {}\n", c.name, c.expr, lang::escape_for_display(c.comment));
    for (const auto& s : net.submodels) {
      out_ += "\n";
      submodel(s);
    }
    body(net.boundaries, net.nodes, net.links, net.heaters, net.instances);
    if (net.case_spec) case_block(*net.case_spec);
    return std::move(out_);
  }

  /// A submodel: its header, params, consts and body, indented.
  void submodel(const Submodel& s) {
    std::string terms;
    for (const auto& t : s.terminals)
      terms += (terms.empty() ? "" : ", ") + t;
    out_ +=
        fmt::format("submodel {}({}) {{{}\n", s.name, terms, origin(s.origin, s.origin, s.what));
    std::string inner;
    std::swap(inner, out_);
    for (const auto& p : s.params)
      out_ += (p.default_ ? fmt::format("param {} = {}", p.name, *p.default_)
                          : fmt::format("param {}", p.name)) +
              origin(p.origin, p.origin, "") + "\n";
    for (const auto& c : s.consts)
      out_ +=
          fmt::format("const {} = {}  # {}\n", c.name, c.expr, lang::escape_for_display(c.comment));
    body(s.boundaries, s.nodes, s.links, s.heaters, s.instances);
    std::swap(inner, out_);
    // Indented by two; the body's blank lines stay blank.
    std::size_t start = 0;
    while (start < inner.size()) {
      std::size_t end = inner.find('\n', start);
      if (end == std::string::npos) end = inner.size();
      if (start == 0 && end == 0) {
        start = 1; // (the body's first blank line)
        continue;
      }
      out_ += (end > start ? "  " : "") + inner.substr(start, end - start) + "\n";
      start = end + 1;
    }
    out_ += "}\n";
  }

private:
  void body(const std::vector<Boundary>& b, const std::vector<Node>& n, const std::vector<Link>& l,
            const std::vector<Heater>& h, const std::vector<InstanceStmt>& inst) {
    if (!b.empty()) out_ += "\n";
    boundaries(b);
    if (!n.empty()) out_ += "\n";
    nodes(n);
    if (!l.empty()) out_ += "\n";
    links(l);
    if (!h.empty()) out_ += "\n";
    heaters(h);
    if (!inst.empty()) out_ += "\n";
    for (const auto& i : inst) {
      std::string line = i.submodel + " " + i.name;
      for (const auto& node : i.nodes)
        line += " " + node;
      for (const auto& [k, v] : i.keys)
        line += " " + k + " = " + v;
      out_ += line + origin(i.origin, i.origin, i.what) + "\n";
    }
  }

  std::uint32_t line_of(lang::Span s) const { return sources_.line_col(s.file, s.begin).line; }

  /// "# file:line" (with `what`), or "# file:first-last" for a run of lines of one file.
  std::string origin(lang::Span first, lang::Span last, const std::string& what) const {
    std::string text = "  # " + place_text(sources_, first);
    const std::uint32_t a = line_of(first), b = line_of(last);
    if (b != a) text += fmt::format("-{}", b);
    if (!what.empty()) text += " " + lang::escape_for_display(what);
    return text;
  }

  static std::string signal(const Signal& s) {
    if (s.points.empty()) return s.constant.text;
    std::string text = "pwl(";
    for (std::size_t i = 0; i < s.points.size(); ++i)
      text +=
          fmt::format("{}{}: {}", i ? ", " : "", s.points[i].first.text, s.points[i].second.text);
    return text + ")";
  }

  /// The index expression `p * i + q` of a loop variable i.
  static std::string index_expr(std::int64_t p, std::int64_t q) {
    std::string lead;
    if (p == 0) return std::to_string(q);
    if (p == 1)
      lead = "i";
    else if (p == -1)
      lead = "-i";
    else
      lead = std::to_string(p) + " * i";
    if (q == 0) return lead;
    return lead + (q > 0 ? " + " : " - ") + std::to_string(q > 0 ? q : -q);
  }

  /// Whether item k continues a run that starts at `first`: same base, the next index.
  static bool next_index(const Name& first, const Name& k, std::size_t steps) {
    return first.index && k.index && k.base == first.base &&
           *k.index == *first.index + static_cast<std::int64_t>(steps);
  }

  /// Whether terminal `k` lies on the progression of the run's terminals (same base).
  static bool on_progression(const Name& t0, const Name& t1, const Name& tk, std::size_t steps) {
    if (!t0.index || !t1.index || !tk.index || tk.base != t0.base || t1.base != t0.base)
      return false;
    return *tk.index - *t0.index == static_cast<std::int64_t>(steps) * (*t1.index - *t0.index);
  }

  void boundaries(const std::vector<Boundary>& list) {
    for (std::size_t i = 0; i < list.size();) {
      const Boundary& b = list[i];
      std::size_t j = i + 1;
      if (b.T.points.empty())
        while (j < list.size() && next_index(b.name, list[j].name, j - i) &&
               list[j].T.points.empty() && list[j].T.constant.text == b.T.constant.text &&
               list[j].what == b.what && list[j].origin.file == b.origin.file)
          ++j;
      if (j - i >= min_node_run)
        out_ += fmt::format("boundary {}[{} .. {}] T = {}{}\n", b.name.base, *b.name.index,
                            *list[j - 1].name.index, b.T.constant.text,
                            origin(b.origin, list[j - 1].origin, b.what));
      else
        out_ += fmt::format("boundary {} T = {}{}\n", b.name.text(), signal(b.T),
                            origin(b.origin, b.origin, b.what));
      i = std::max(j, i + 1);
    }
  }

  void nodes(const std::vector<Node>& list) {
    const auto t0 = [](const Node& n) { return n.T0 ? " T0 = " + n.T0->text : std::string(); };
    for (std::size_t i = 0; i < list.size();) {
      const Node& n = list[i];
      std::size_t j = i + 1;
      while (j < list.size() && next_index(n.name, list[j].name, j - i) &&
             list[j].C.text == n.C.text && t0(list[j]) == t0(n) && list[j].what == n.what &&
             list[j].origin.file == n.origin.file)
        ++j;
      if (j - i >= min_node_run)
        out_ += fmt::format("node {}[{} .. {}] C = {}{}{}\n", n.name.base, *n.name.index,
                            *list[j - 1].name.index, n.C.text, t0(n),
                            origin(n.origin, list[j - 1].origin, n.what));
      else
        out_ += fmt::format("node {} C = {}{}{}\n", n.name.text(), n.C.text, t0(n),
                            origin(n.origin, n.origin, n.what));
      i = j;
    }
  }

  static const char* kind_word(LinkKind k) {
    switch (k) {
    case LinkKind::conductance:
      return "conductance";
    case LinkKind::resistor:
      return "resistor";
    case LinkKind::radiation:
      return "radiation";
    }
    return "conductance";
  }

  static const char* key_word(LinkKind k) {
    switch (k) {
    case LinkKind::conductance:
      return "G";
    case LinkKind::resistor:
      return "R";
    case LinkKind::radiation:
      return "GR";
    }
    return "G";
  }

  void links(const std::vector<Link>& list) {
    for (std::size_t i = 0; i < list.size();) {
      const Link& l = list[i];
      std::size_t j = i + 1;
      if (i + 1 < list.size()) {
        const Link& m = list[i + 1];
        while (j < list.size() && list[j].kind == l.kind &&
               next_index(l.name, list[j].name, j - i) &&
               on_progression(l.a, m.a, list[j].a, j - i) &&
               on_progression(l.b, m.b, list[j].b, j - i) && list[j].value.text == l.value.text &&
               list[j].what == l.what && list[j].origin.file == l.origin.file)
          ++j;
      }
      if (j - i >= min_loop_run) {
        const std::int64_t lo = *l.name.index, hi = *list[j - 1].name.index;
        const std::int64_t pa = *list[i + 1].a.index - *l.a.index;
        const std::int64_t pb = *list[i + 1].b.index - *l.b.index;
        out_ += fmt::format("for i in {} .. {} {{ {} {}[i] {}[{}] {}[{}] {} = {} }}{}\n", lo, hi,
                            kind_word(l.kind), l.name.base, l.a.base,
                            index_expr(pa, *l.a.index - pa * lo), l.b.base,
                            index_expr(pb, *l.b.index - pb * lo), key_word(l.kind), l.value.text,
                            origin(l.origin, list[j - 1].origin, l.what));
        i = j;
        continue;
      }
      out_ += fmt::format("{} {} {} {} {} = {}{}\n", kind_word(l.kind), l.name.text(), l.a.text(),
                          l.b.text(), key_word(l.kind), l.value.text,
                          origin(l.origin, l.origin, l.what));
      ++i;
    }
  }

  void heaters(const std::vector<Heater>& list) {
    const auto simple = [](const Heater& h) { return h.origins.size() == 1 && h.P.points.empty(); };
    for (std::size_t i = 0; i < list.size();) {
      const Heater& h = list[i];
      std::size_t j = i + 1;
      if (simple(h) && i + 1 < list.size()) {
        const Heater& m = list[i + 1];
        while (j < list.size() && simple(list[j]) && next_index(h.name, list[j].name, j - i) &&
               on_progression(h.node, m.node, list[j].node, j - i) &&
               list[j].P.constant.text == h.P.constant.text && list[j].what == h.what &&
               list[j].origins[0].file == h.origins[0].file)
          ++j;
      }
      if (j - i >= min_loop_run) {
        const std::int64_t lo = *h.name.index, hi = *list[j - 1].name.index;
        const std::int64_t p = *list[i + 1].node.index - *h.node.index;
        out_ +=
            fmt::format("for i in {} .. {} {{ heater {}[i] {}[{}] P = {} }}{}\n", lo, hi,
                        h.name.base, h.node.base, index_expr(p, *h.node.index - p * lo),
                        h.P.constant.text, origin(h.origins[0], list[j - 1].origins[0], h.what));
        i = j;
        continue;
      }
      std::string where;
      for (const auto& o : h.origins)
        where += (where.empty() ? "  # " : ", ") + place_text(sources_, o);
      if (!h.what.empty()) where += " " + lang::escape_for_display(h.what);
      out_ +=
          fmt::format("heater {} {} P = {}{}\n", h.name.text(), h.node.text(), signal(h.P), where);
      ++i;
    }
  }

  void case_block(const CaseSpec& c) {
    out_ += fmt::format("\ncase {} {{{}\n", c.name, origin(c.origin, c.origin, ""));
    out_ += fmt::format("  duration = {}\n", c.duration.text);
    if (c.output) out_ += fmt::format("  output = {}\n", c.output->text);
    if (!c.initial.empty()) out_ += fmt::format("  initial = {}\n", c.initial);
    out_ += "}\n";
  }

  const lang::SourceManager& sources_;
  std::string out_;
};

} // namespace

std::string write_tnet(const Network& net, const std::vector<Remark>& remarks,
                       const lang::SourceManager& sources) {
  return Writer(sources).write(net, remarks);
}

std::string write_submodel(const Submodel& s, const lang::SourceManager& sources) {
  Writer w(sources);
  w.submodel(s);
  return w.text();
}

} // namespace thermnet::importer
