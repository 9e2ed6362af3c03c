#include "import/sinda_fields.hpp"

#include "import/fortran_number.hpp"
#include "import/report.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

namespace thermnet::importer::sinda {

bool blank(char c) {
  return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == 0x1a;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && blank(s.front()))
    s.remove_prefix(1);
  while (!s.empty() && blank(s.back()))
    s.remove_suffix(1);
  return s;
}

bool is_comment_line(std::string_view line) {
  return !line.empty() && (line[0] == 'C' || line[0] == 'c') &&
         (line.size() == 1 || blank(line[1]));
}

std::string_view strip_comment(std::string_view line) {
  if (const auto dollar = line.find('$'); dollar != std::string_view::npos)
    line = line.substr(0, dollar);
  while (!line.empty() && blank(line.back()))
    line.remove_suffix(1);
  return line;
}

std::vector<Field> split_fields(const SourceLine& line) {
  const std::string_view text = strip_comment(line.text);
  std::vector<Field> fields;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t comma = text.find(',', start);
    const bool last = comma == std::string_view::npos;
    if (last) comma = text.size();
    // Blank-separated words within the comma-separated part.
    std::size_t i = start;
    bool any = false;
    while (i < comma) {
      while (i < comma && blank(text[i]))
        ++i;
      if (i >= comma) break;
      std::size_t j = i;
      while (j < comma && !blank(text[j]))
        ++j;
      fields.push_back({text.substr(i, j - i), line.span(i, j)});
      any = true;
      i = j;
    }
    if (!any && !(last && start == text.size() && fields.empty()))
      throw ImportError(line.span(start, start + 1), "bad-syntax",
                        last && start == text.size() ? "a line may not end with a comma"
                                                     : "an empty field between two commas");
    if (last) break;
    start = comma + 1;
  }
  return fields;
}

double real_field(const Field& f) {
  const RealResult r = parse_fortran_real(f.text);
  if (r.problem != NumberProblem::none)
    throw ImportError(f.at, "bad-number", fortran_number_message(f.text, r.problem));
  return r.value;
}

std::int64_t integer_field(const Field& f, const char* what) {
  if (auto v = parse_fortran_integer(f.text)) return *v;
  throw ImportError(
      f.at, "bad-number",
      fmt::format("{} must be a whole number, not '{}'", what, lang::excerpt_for_display(f.text)));
}

NodeRef node_field(const Field& f, const std::string& block_sub) {
  NodeRef ref;
  ref.at = f.at;
  std::string_view id = f.text;
  if (const auto dot = f.text.find('.'); dot != std::string_view::npos) {
    ref.sub = upper(f.text.substr(0, dot));
    id = f.text.substr(dot + 1);
    if (!is_identifier(ref.sub))
      throw ImportError(f.at, "bad-syntax",
                        fmt::format("'{}' is not a node: write ID or SUBMODEL.ID (e.g. MAIN.12)",
                                    lang::excerpt_for_display(f.text)));
  } else {
    ref.sub = block_sub;
  }
  auto v = parse_fortran_integer(id);
  if (!v || *v == 0)
    throw ImportError(f.at, "bad-syntax",
                      fmt::format("'{}' is not a node: write ID or SUBMODEL.ID (e.g. MAIN.12)",
                                  lang::excerpt_for_display(f.text)));
  ref.id = *v;
  return ref;
}

std::string upper(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  return out;
}

bool is_identifier(std::string_view name) {
  if (name.empty()) return false;
  const auto alpha = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
  };
  if (!alpha(name[0])) return false;
  for (const char c : name)
    if (!alpha(c) && !(c >= '0' && c <= '9')) return false;
  return true;
}

} // namespace thermnet::importer::sinda
