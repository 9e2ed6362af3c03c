// Elaboration of `require` statements (Elaborator::add_requirements): groups resolved to the
// case's nodes or sources, limits evaluated into SI with the unit they were written in kept for
// reports.

#include "lang/elaborator.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>

#include <fnmatch.h>

#include <algorithm>
#include <cmath>

namespace thermnet::lang {

const char* requirement_keyword(RequirementKind k) {
  switch (k) {
  case RequirementKind::band:
    return "band";
  case RequirementKind::gradient:
    return "gradient";
  case RequirementKind::power:
    return "power";
  case RequirementKind::energy:
    return "energy";
  case RequirementKind::margin:
    return "margin";
  }
  return "?";
}

namespace {

Span span_in(FileId f, const ast::Tagged& t) {
  return Span{f, t.begin, t.end};
}

std::optional<RequirementKind> kind_of(std::string_view word) {
  for (auto k : {RequirementKind::band, RequirementKind::gradient, RequirementKind::power,
                 RequirementKind::energy, RequirementKind::margin})
    if (word == requirement_keyword(k)) return k;
  return std::nullopt;
}

/// The unit reports use when the limit is written without one.
DisplayUnit default_unit(RequirementKind k) {
  switch (k) {
  case RequirementKind::band:
    return {"degC", 1.0, kZeroCelsius};
  case RequirementKind::gradient:
    return {"K", 1.0, 0.0};
  case RequirementKind::power:
    return {"W", 1.0, 0.0};
  case RequirementKind::energy:
    return {"J", 1.0, 0.0};
  case RequirementKind::margin:
    return {"%", 0.01, 0.0};
  }
  return {};
}

Dimension dimension_of(RequirementKind k) {
  switch (k) {
  case RequirementKind::band:
  case RequirementKind::gradient:
    return dim::temperature;
  case RequirementKind::power:
    return dim::power;
  case RequirementKind::energy:
    return dim::energy;
  case RequirementKind::margin:
    return dim::none;
  }
  return dim::none;
}

/// The indices of `names` a pattern selects: the name itself, else those the glob matches.
std::vector<int> select(const std::vector<std::string>& names, const std::string& pattern,
                        const std::function<bool(std::size_t)>& eligible) {
  std::vector<int> out;
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == pattern && eligible(i)) return {static_cast<int>(i)};
  for (std::size_t i = 0; i < names.size(); ++i)
    if (eligible(i) && ::fnmatch(pattern.c_str(), names[i].c_str(), 0) == 0)
      out.push_back(static_cast<int>(i));
  return out;
}

} // namespace

void Elaborator::add_requirements(NetworkSpec& net) {
  net.requirements.clear();
  if (m_.requirements().empty()) return;
  std::vector<std::string> node_names, element_names;
  for (const auto& n : net.nodes)
    node_names.push_back(n.name);
  for (const auto& e : net.elements)
    element_names.push_back(e.name);
  const std::vector<std::string> cases = m_.case_names();
  for (const RequirementDecl& decl : m_.requirements()) {
    const ast::RequireStmt& s = *decl.stmt;
    const FileId f = decl.file;
    const Span at{f, s.begin, s.begin};
    const auto fail = [&](const ast::Tagged& mark, std::string message) {
      report(DiagnosticEngine::make(DiagId::bad_requirement, at, span_in(f, mark),
                                    std::move(message)));
    };
    const auto kind = kind_of(s.kind.name);
    if (!kind) continue; // the grammar admits only the kinds
    // Which cases: `in CASE, ...` names declared cases; the requirement applies to those.
    bool applies = s.cases.empty();
    bool bad = false;
    for (const auto& c : s.cases) {
      if (std::find(cases.begin(), cases.end(), c.name) == cases.end()) {
        std::string msg = fmt::format("requirement names unknown case '{}'", c.name);
        if (auto near = closest_match(std::string(c.name), cases))
          msg += fmt::format("; did you mean '{}'?", *near);
        else if (cases.empty())
          msg += " (the model declares no case)";
        fail(c, msg);
        bad = true;
      }
      applies = applies || c.name == net.settings.name;
    }
    if (bad || !applies) continue;
    // The form of the limit must fit the kind.
    const bool band = *kind == RequirementKind::band;
    const char* want_bound = *kind == RequirementKind::margin ? "min" : "max";
    if (band && !s.lo) {
      fail(s.limit, "a band requirement takes a range 'LO .. HI' (e.g. 15 .. 25 [degC])");
      continue;
    }
    if (!band && s.bound.name != want_bound) {
      fail(s.lo ? static_cast<const ast::Tagged&>(*s.lo) : s.bound,
           fmt::format("a {} requirement takes '{} VALUE' (e.g. 'require {} \"{}\" {} {}')",
                       s.kind.name, want_bound, s.kind.name, s.groups.front().text, want_bound,
                       *kind == RequirementKind::gradient ? "5 [K]"
                       : *kind == RequirementKind::power  ? "100 [W]"
                       : *kind == RequirementKind::energy ? "500 [kJ]"
                                                          : "50 [%]"));
      continue;
    }
    const std::size_t max_groups = *kind == RequirementKind::gradient ? 2 : s.groups.size();
    if (s.groups.size() > max_groups) {
      fail(s.groups[2], "a gradient requirement takes one group (the spread within it) or two "
                        "(the largest difference between them)");
      continue;
    }
    RequirementSpec r;
    r.kind = *kind;
    r.where = decl.where;
    r.doc = s.doc ? s.doc->text : "";
    const std::string& text = m_.sources().text(f);
    r.text = text.substr(s.begin, s.end - s.begin);
    while (!r.text.empty() && (r.text.back() == ' ' || r.text.back() == '\n'))
      r.text.pop_back();
    // Members: nodes for band and gradient, one-terminal sources for the others.
    const bool on_nodes = band || *kind == RequirementKind::gradient;
    for (std::size_t g = 0; g < s.groups.size(); ++g) {
      const std::string& pattern = s.groups[g].text;
      std::vector<int> picked;
      if (on_nodes) {
        picked = select(node_names, pattern, [](std::size_t) { return true; });
      } else {
        picked = select(element_names, pattern, [&](std::size_t i) {
          const ElementSpec& e = net.elements[i];
          return e.nodes().size() == 1 && e.composite() == Composite::none;
        });
      }
      if (picked.empty()) {
        const bool literal = pattern.find_first_of("*?[") == std::string::npos;
        std::vector<std::string> candidates;
        if (on_nodes) {
          candidates = node_names;
        } else {
          for (std::size_t i = 0; i < element_names.size(); ++i)
            if (net.elements[i].nodes().size() == 1) candidates.push_back(element_names[i]);
        }
        const auto existing = std::find(element_names.begin(), element_names.end(), pattern);
        std::string msg;
        if (on_nodes)
          msg = literal ? fmt::format("unknown node '{}'", pattern)
                        : fmt::format("pattern '{}' matches no node or boundary", pattern);
        else if (literal && existing != element_names.end())
          msg = fmt::format(
              "'{}' is a {}, not a heat source (a one-terminal element such as a "
              "heater or thermostat)",
              pattern,
              net.elements[static_cast<std::size_t>(existing - element_names.begin())].kind());
        else
          msg = literal ? fmt::format("unknown heat source '{}'", pattern)
                        : fmt::format("pattern '{}' matches no heat source (a one-terminal "
                                      "element such as a heater or thermostat)",
                                      pattern);
        Diagnostic d = DiagnosticEngine::make(on_nodes ? DiagId::requirement_unknown_node
                                                       : DiagId::requirement_unknown_source,
                                              at, span_in(f, s.groups[g]), msg);
        if (literal && existing == element_names.end())
          if (auto near = closest_match(pattern, candidates))
            d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, *near));
        report(std::move(d));
        bad = true;
        continue;
      }
      r.groups.push_back(pattern);
      auto& into = (*kind == RequirementKind::gradient && g == 1) ? r.others : r.members;
      for (int i : picked)
        if (std::find(into.begin(), into.end(), i) == into.end()) into.push_back(i);
    }
    if (bad) continue;
    if (*kind == RequirementKind::margin)
      for (int e : r.members)
        if (!net.elements[static_cast<std::size_t>(e)].has("P") ||
            !net.elements[static_cast<std::size_t>(e)].values.at("P").is_constant()) {
          fail(s.groups.front(),
               fmt::format("a margin compares a source's installed power 'P' with what it "
                           "delivers; '{}' has no constant 'P'",
                           net.elements[static_cast<std::size_t>(e)].name));
          bad = true;
          break;
        }
    if (bad) continue;
    // Limits: a lone `NUMBER [UNIT]` sets the unit of reports (and of a bare lower end).
    const ast::File& file = m_.file(f);
    const Dimension want = dimension_of(*kind);
    const bool absolute = band;
    r.unit = default_unit(*kind);
    std::optional<Unit> written;
    const ast::ExprNode& root = file.node(s.limit.root);
    if (root.op == ast::ExprNode::Op::quantity) {
      try {
        written = parse_unit(file.units[root.a].text);
        r.unit = {file.units[root.a].text, written->scale, absolute ? written->offset : 0.0};
      } catch (const UnitError&) {
        // reported by the evaluation below
      }
    }
    const auto value = [&](const ast::Expr& e, bool lone_unit_applies) -> std::optional<double> {
      try {
        const ast::ExprNode& n = file.node(e.root);
        Quantity q = evaluate(e, f, nullptr);
        if (q.dim && !(*q.dim == want) && !(want == dim::none && q.dim->dimensionless())) {
          report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_in(f, e),
                                        fmt::format("the limit of a {} requirement", s.kind.name),
                                        describe(want), describe(*q.dim)));
          return std::nullopt;
        }
        if (n.op == ast::ExprNode::Op::quantity && written && !absolute)
          return written->scale * n.value; // a difference: `5 [degC]` is 5 K
        if (!q.dim && lone_unit_applies && written)
          return written->scale * q.value + (absolute ? written->offset : 0.0);
        return q.value + bare_temperature_offset(q, absolute);
      } catch (const EvalError& err) {
        report_at(err, at);
        return std::nullopt;
      }
    };
    const auto limit = value(s.limit, false);
    if (!limit) continue;
    if (band) {
      const auto lo = value(*s.lo, true);
      if (!lo) continue;
      r.lo = *lo;
      r.hi = *limit;
      if (r.lo > r.hi) {
        fail(s.limit, fmt::format("the band is empty: {:g} .. {:g} {}", r.unit.shown(r.lo),
                                  r.unit.shown(r.hi), r.unit.text));
        continue;
      }
    } else if (*kind == RequirementKind::margin) {
      r.lo = *limit;
    } else {
      r.hi = *limit;
    }
    if ((*kind != RequirementKind::band && *limit < 0) || !std::isfinite(*limit)) {
      fail(s.limit,
           fmt::format("the limit of a {} requirement must be a finite value >= 0", s.kind.name));
      continue;
    }
    if (s.from) {
      try {
        Quantity q = evaluate(*s.from, f, nullptr);
        if (q.dim && !(*q.dim == dim::time)) {
          report(DiagnosticEngine::make(DiagId::unit_mismatch, at, span_in(f, *s.from),
                                        "'from' (a time)", describe(dim::time), describe(*q.dim)));
          continue;
        }
        r.from = q.value;
      } catch (const EvalError& err) {
        report_at(err, at);
        continue;
      }
    }
    net.requirements.push_back(std::move(r));
  }
}

} // namespace thermnet::lang
