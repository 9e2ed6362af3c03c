#include "lang/rewrite/case_blocks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string_view>

namespace thermnet::rewrite {

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
      insert += fmt::format("  {} {}\n", rest.substr(0, eol), comment);
      rest.remove_prefix(std::min(eol + 1, rest.size()));
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
