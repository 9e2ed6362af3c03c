// Scopes of generated declarations: loop variables, instances, and the context notes of their
// diagnostics.

#include "lang/model.hpp"

#include <fmt/format.h>

namespace thermnet::lang {

Scope Scope::loop(const Scope* parent, FileId file, std::uint32_t begin,
                  const std::vector<ast::LoopRange>& ranges) {
  Scope s;
  s.kind = Kind::loop;
  s.parent = parent;
  s.file = file;
  s.where = Span{file, begin, ranges.back().end};
  s.ranges = &ranges;
  return s;
}

const Scope* Scope::instance() const {
  const Scope* s = this;
  while (s && s->kind != Kind::instance)
    s = s->parent;
  return s;
}

std::optional<long> Scope::variable(std::string_view name) const {
  for (const Scope* s = this; s && s->kind == Kind::loop; s = s->parent)
    for (std::size_t k = 0; k < s->values.size(); ++k)
      if ((*s->ranges)[k].var.name == name) return s->values[k];
  return std::nullopt;
}

void add_scope_notes(Diagnostic& d, const Scope* scope) {
  if (!scope) return;
  d.generated = true;
  for (const Scope* s = scope; s;) {
    if (s->kind == Scope::Kind::instance) {
      d.notes.push_back(DiagnosticEngine::note(DiagId::instance_note,
                                               Span{s->file, s->where.begin, s->where.begin},
                                               s->name, s->submodel->name));
      d.notes.back().mark = s->where;
      s = s->parent;
      continue;
    }
    // Loops nested directly in each other make one note, outer variables first.
    std::vector<const Scope*> loops;
    for (; s && s->kind == Scope::Kind::loop; s = s->parent)
      loops.push_back(s);
    std::string values;
    for (auto it = loops.rbegin(); it != loops.rend(); ++it)
      for (std::size_t k = 0; k < (*it)->values.size(); ++k)
        values += fmt::format("{}{} = {}", values.empty() ? "" : ", ", (*(*it)->ranges)[k].var.name,
                              (*it)->values[k]);
    const Scope* outer = loops.back();
    d.notes.push_back(DiagnosticEngine::note(
        DiagId::iteration_note, Span{outer->file, outer->where.begin, outer->where.begin}, values));
    d.notes.back().mark = outer->where;
  }
}

bool GeneratedPlaces::first(const Diagnostic& d, const Scope* scope) {
  if (!scope && !d.generated) return true;
  const Span a = d.at.value_or(Span{}), mark = d.mark.value_or(a);
  return seen_.emplace(d.code, mark.file, mark.begin, a.file, a.begin).second;
}

bool GeneratedPlaces::seen(const Diagnostic& d, const Scope* scope) const {
  if (!scope && !d.generated) return false;
  const Span mark = d.mark.value_or(d.at.value_or(Span{}));
  const auto it = seen_.lower_bound({d.code, mark.file, mark.begin, FileId{0}, 0u});
  return it != seen_.end() && std::get<0>(*it) == d.code && std::get<1>(*it) == mark.file &&
         std::get<2>(*it) == mark.begin;
}

int SubmodelDecl::value_index(std::string_view n) const {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (values[i].name == n) return static_cast<int>(i);
  return -1;
}

int SubmodelDecl::terminal_index(std::string_view n) const {
  for (std::size_t i = 0; i < stmt->terminals.size(); ++i)
    if (stmt->terminals[i].name == n) return static_cast<int>(i);
  return -1;
}

} // namespace thermnet::lang
