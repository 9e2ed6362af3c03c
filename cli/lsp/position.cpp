#include "cli/lsp/position.hpp"

#include <algorithm>

namespace thermnet::cli::lsp {
namespace {

/// Length in bytes of the UTF-8 sequence starting with `lead` (1 for stray continuation bytes).
std::size_t sequence_length(unsigned char lead) {
  if (lead >= 0xF0) return 4;
  if (lead >= 0xE0) return 3;
  if (lead >= 0xC0) return 2;
  return 1;
}

} // namespace

Position position_at(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  Position p;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < offset; ++i)
    if (text[i] == '\n') {
      ++p.line;
      line_start = i + 1;
    }
  for (std::size_t i = line_start; i < offset;) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t n = sequence_length(c);
    if (i + n > offset) break; // an offset inside a sequence counts up to its start
    p.character += n == 4 ? 2 : 1;
    i += n;
  }
  return p;
}

std::size_t offset_at(std::string_view text, Position p) {
  std::size_t i = 0;
  for (int line = 0; line < p.line; ++line) {
    std::size_t nl = text.find('\n', i);
    if (nl == std::string_view::npos) return text.size();
    i = nl + 1;
  }
  int units = 0;
  auto line_end = [&](std::size_t k) {
    return text[k] == '\n' || (text[k] == '\r' && k + 1 < text.size() && text[k + 1] == '\n');
  };
  while (i < text.size() && !line_end(i) && units < p.character) {
    const std::size_t n = sequence_length(static_cast<unsigned char>(text[i]));
    units += n == 4 ? 2 : 1;
    i = std::min(text.size(), i + n);
  }
  return i;
}

nlohmann::json range_json(std::string_view text, std::size_t begin, std::size_t end) {
  Position b = position_at(text, begin);
  Position e = position_at(text, std::max(begin, end));
  return {{"start", {{"line", b.line}, {"character", b.character}}},
          {"end", {{"line", e.line}, {"character", e.character}}}};
}

Position position_from_json(const nlohmann::json& j) {
  return Position{j.at("line").get<int>(), j.at("character").get<int>()};
}

} // namespace thermnet::cli::lsp
