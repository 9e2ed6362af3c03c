#pragma once
/// Edits of a model file's text: byte ranges replaced, everything else kept byte-identical.

#include <cstdint>
#include <string>
#include <vector>

namespace thermnet::rewrite {

/// A replacement of the bytes [begin, end) of one file's text.
struct TextEdit {
  std::uint32_t begin = 0; ///< first byte replaced
  std::uint32_t end = 0;   ///< one past the last byte replaced
  std::string text;        ///< the new bytes
};

/// Applies non-overlapping edits (in any order) to a text.
std::string apply_edits(std::string text, std::vector<TextEdit> edits);

/// True for a blank or a line break (space, tab, CR, LF).
bool is_blank(char c);

} // namespace thermnet::rewrite
