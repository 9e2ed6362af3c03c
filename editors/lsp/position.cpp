#include "editors/lsp/position.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>

namespace thermnet::lsp {
namespace {

/// Length in bytes of the UTF-8 sequence starting with `lead` (1 for stray continuation bytes).
std::size_t sequence_length(unsigned char lead) {
  if (lead >= 0xF0) return 4;
  if (lead >= 0xE0) return 3;
  if (lead >= 0xC0) return 2;
  return 1;
}

/// UTF-16 code units from `line_start` up to `offset` (an offset inside a sequence counts up to
/// its start).
int utf16_units(std::string_view text, std::size_t line_start, std::size_t offset) {
  int units = 0;
  for (std::size_t i = line_start; i < offset;) {
    const std::size_t n = sequence_length(static_cast<unsigned char>(text[i]));
    if (i + n > offset) break;
    units += n == 4 ? 2 : 1;
    i += n;
  }
  return units;
}

} // namespace

Position position_at(std::string_view text, std::size_t offset) {
  return LineIndex(text.substr(0, std::min(offset, text.size()))).position(offset);
}

LineIndex::LineIndex(std::string_view text) : text_(text), starts_{0} {
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') starts_.push_back(i + 1);
}

Position LineIndex::position(std::size_t offset) const {
  offset = std::min(offset, text_.size());
  // The last line start not after `offset` (starts_[0] == 0, so never begin()).
  const auto it = std::upper_bound(starts_.begin(), starts_.end(), offset) - 1;
  Position p;
  p.line = static_cast<int>(it - starts_.begin());
  p.character = utf16_units(text_, *it, offset);
  return p;
}

nlohmann::json LineIndex::range(std::size_t begin, std::size_t end) const {
  const Position b = position(begin);
  const Position e = position(std::max(begin, end));
  return {{"start", {{"line", b.line}, {"character", b.character}}},
          {"end", {{"line", e.line}, {"character", e.character}}}};
}

void LineIndex::append_range(std::string& out, std::size_t begin, std::size_t end) const {
  const Position b = position(begin);
  const Position e = position(std::max(begin, end));
  fmt::format_to(std::back_inserter(out),
                 R"({{"end":{{"character":{},"line":{}}},"start":{{"character":{},"line":{}}}}})",
                 e.character, e.line, b.character, b.line);
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
  return LineIndex(text.substr(0, std::min(std::max(begin, end), text.size()))).range(begin, end);
}

Position position_from_json(const nlohmann::json& j) {
  return Position{j.at("line").get<int>(), j.at("character").get<int>()};
}

} // namespace thermnet::lsp
