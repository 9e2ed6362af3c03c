#pragma once
/// The words that start a statement of the language: reserved, they cannot name anything.

#include <algorithm>
#include <array>
#include <string_view>

namespace thermnet::lang {

/// Statement keywords (`data` and `range` are keywords only in their places and stay usable names).
inline constexpr std::array<std::string_view, 10> statement_keywords = {
    "model", "include",  "plugin", "const",    "param",
    "node",  "boundary", "series", "parallel", "case"};

/// True when `word` is a statement keyword.
inline bool is_keyword(std::string_view word) {
  return std::find(statement_keywords.begin(), statement_keywords.end(), word) !=
         statement_keywords.end();
}

} // namespace thermnet::lang
