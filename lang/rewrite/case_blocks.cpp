#include "lang/rewrite/case_blocks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string_view>
#include <variant>

namespace thermnet::rewrite {
namespace {

/// `text` without blanks, to compare targets as written (`p[1, 2].C` is `p[1,2].C`).
std::string without_blanks(std::string_view text) {
  std::string out;
  for (char ch : text)
    if (!is_blank(ch)) out += ch;
  return out;
}

/// The setting of `target` (blanks ignored) at the top of a case's block, if any (a setting may
/// appear once per case: a new one replaces it).
const lang::ast::CaseAssign* setting_of(const lang::ast::CaseStmt& c, const std::string& text,
                                        const std::string& target) {
  for (const auto& item : c.items)
    if (const auto* a = std::get_if<lang::ast::CaseAssign>(&item))
      if (without_blanks(std::string_view(text).substr(a->target.begin,
                                                       a->target.end - a->target.begin)) == target)
        return a;
  return nullptr;
}

} // namespace

std::vector<TextEdit> case_block_edits(const lang::Model& model, lang::FileId file,
                                       const std::map<std::string, std::string>& lines,
                                       const std::string& comment,
                                       std::vector<std::string>& elsewhere) {
  const std::string& text = model.sources().text(file);
  std::vector<TextEdit> edits;
  for (const auto& [name, body] : lines) {
    const auto c = std::find_if(model.cases().begin(), model.cases().end(),
                                [&](const lang::CaseDecl& d) { return d.name == name; });
    if (c == model.cases().end() || c->file != file || c->where.end == 0 ||
        c->where.end > text.size() || text[c->where.end - 1] != '}') {
      elsewhere.push_back(name);
      continue;
    }
    std::string insert = "\n";
    std::string_view rest = body;
    while (!rest.empty()) {
      const std::size_t eol = std::min(rest.find('\n'), rest.size());
      const std::string_view line = rest.substr(0, eol);
      rest.remove_prefix(std::min(eol + 1, rest.size()));
      // A key the case sets already is set in its place (a second setting would be an error).
      const std::string target = without_blanks(line.substr(0, line.find('=')));
      if (const auto* a = line.find('=') == std::string_view::npos
                              ? nullptr
                              : setting_of(*c->stmt, text, target)) {
        edits.push_back({a->begin, a->end, std::string(line)});
        insert += fmt::format("  {} (sets {} in its place above)\n", comment, target);
        continue;
      }
      insert += fmt::format("  {} {}\n", line, comment);
    }
    // Replaces the blanks before the brace, so that no line is left with trailing blanks.
    std::uint32_t from = c->where.end - 1;
    while (from > c->where.begin && is_blank(text[from - 1]))
      --from;
    edits.push_back({from, c->where.end - 1, std::move(insert)});
  }
  return edits;
}

} // namespace thermnet::rewrite
