#pragma once
/// LSP positions (0-based line, UTF-16 code units) versus byte offsets into UTF-8 text.

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::lsp {

/// A position as the protocol counts it.
struct Position {
  int line = 0;      ///< 0-based line
  int character = 0; ///< UTF-16 code units from the line start
};

/// The position of a byte offset (clamped to the text's end).
Position position_at(std::string_view text, std::size_t offset);

/// The byte offset of a position (a character past the line's end clamps to it).
std::size_t offset_at(std::string_view text, Position p);

/// `{"start": ..., "end": ...}` of the byte range [begin, end).
nlohmann::json range_json(std::string_view text, std::size_t begin, std::size_t end);

/// The line starts of a text, for positions of many offsets in time proportional to their lines
/// (position_at() scans from the start of the text each time).
class LineIndex {
public:
  /// Indexes `text`, which must outlive the index.
  explicit LineIndex(std::string_view text);
  /// The position of a byte offset (clamped to the text's end), like position_at().
  Position position(std::size_t offset) const;
  /// `{"start": ..., "end": ...}` of the byte range [begin, end), like range_json().
  nlohmann::json range(std::size_t begin, std::size_t end) const;
  /// Appends the JSON text of range() to `out` (no json tree built).
  void append_range(std::string& out, std::size_t begin, std::size_t end) const;

private:
  std::string_view text_;
  std::vector<std::size_t> starts_;
};

/// Reads `{"line": L, "character": C}`; throws nlohmann::json::exception when malformed.
Position position_from_json(const nlohmann::json& j);

} // namespace thermnet::lsp
