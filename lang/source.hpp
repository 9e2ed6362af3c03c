#pragma once
/// Source files of a model: text, paths and offset -> line/column mapping.

#include <cstdint>
#include <deque>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::lang {

/// Index of a file held by a SourceManager.
using FileId = std::uint32_t;

/// A half-open byte range [begin, end) inside one source file.
struct Span {
  FileId file = 0;         ///< which file
  std::uint32_t begin = 0; ///< first byte
  std::uint32_t end = 0;   ///< one past the last byte
};

/// A 1-based line and column (column counts UTF-8 code points).
struct LineCol {
  std::uint32_t line = 1;   ///< 1-based line
  std::uint32_t column = 1; ///< 1-based column
};

/// Largest file read as a model, include or data file (offsets in a Span are 32-bit).
inline constexpr std::size_t max_file_bytes = std::size_t{1} << 30;

/// Reads a whole file into `text`; returns an error message instead for a path the process-wide
/// PathPolicy refuses (outside the model's folder tree), a directory, a FIFO, a device, a file of
/// /proc or /sys, a file larger than max_file_bytes (checked with fstat before reading) or an
/// unreadable file. Never blocks on a FIFO.
std::optional<std::string> read_text_file(const std::string& path, std::string& text);

/// Owns the text of every file read for a model and maps offsets to lines and columns.
class SourceManager {
public:
  /// Adds a file from memory and returns its id.
  FileId add(std::string path, std::string text);
  /// Number of files held.
  std::size_t size() const { return files_.size(); }
  /// The path a file was added under.
  const std::string& path(FileId id) const { return files_.at(id).path; }
  /// The full text of a file; it stays at the same address while the manager lives (syntax trees
  /// view it).
  const std::string& text(FileId id) const { return files_.at(id).text; }
  /// Line and column of a byte offset (offsets past the end clamp to the end).
  LineCol line_col(FileId id, std::uint32_t offset) const;
  /// The text of a 1-based line, without its line break.
  std::string_view line_text(FileId id, std::uint32_t line) const;
  /// The id of a file already added under this path, or -1.
  long find(const std::string& path) const;

private:
  struct File {
    std::string path;
    std::string text;
    std::vector<std::uint32_t> line_starts;
  };
  std::deque<File> files_; // a deque: adding a file never moves the others' text
};

} // namespace thermnet::lang
