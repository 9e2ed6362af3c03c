#pragma once
/// Reading the files an import names: the command line's files and those they include (SINDA's
/// INSERT, SPICE's .include), each a regular text file under the path policy, with include
/// cycles and nesting beyond max_include_depth refused; and their lines with source positions.

#include "import/report.hpp"
#include "lang/source.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::importer {

/// How deep includes may nest.
inline constexpr std::size_t max_include_depth = 64;

/// One line of an input file, without its line break (nor a trailing carriage return).
struct SourceLine {
  lang::FileId file = 0;    ///< which file
  std::uint32_t offset = 0; ///< byte offset of its first character in the file
  std::uint32_t number = 0; ///< 1-based line number
  std::string_view text;    ///< its text (viewing the SourceManager's copy)
  /// The span of the characters [from, to) of the line.
  lang::Span span(std::size_t from, std::size_t to) const;
  /// The span of the whole line (its first character when it is empty).
  lang::Span whole() const;
};

/// The lines of a file held by `sources`.
std::vector<SourceLine> lines_of(const lang::SourceManager& sources, lang::FileId file);

/// A file that cannot be imported: unreadable (missing, not a regular file, refused by the path
/// policy: exit status 2) or not text (a binary file: exit status 1).
struct InputFileError : std::runtime_error {
  /// A problem reading `path`.
  InputFileError(const std::string& path, const std::string& reason, bool unreadable);
  std::string path;   ///< the file
  std::string reason; ///< why, e.g. "No such file or directory"
  bool unreadable;    ///< true: cannot be read; false: read but binary
};

/// Reads a file into `sources` (once: a path read before gives the same id); throws
/// InputFileError for a file that cannot be read or holds a NUL byte or other control characters
/// text does not have (a binary file).
lang::FileId read_input(const std::string& path, lang::SourceManager& sources);

/// The files being read, outermost first: what an include may not name again. Every file is read
/// once: a file read before (named twice, or named and also included) is noted and not read
/// again, since its nodes and conductors would be defined twice.
class IncludeStack {
public:
  /// Starts reading a file named on the command line; false (noted) when it was read before.
  bool push_root(const std::string& path, Report& report);
  /// Reads the file an include statement at `at` names (relative to the folder of the file that
  /// names it) and enters it; reports a missing, unreadable or binary file, a cycle or too deep a
  /// nesting at `at` and returns nothing, as for a file read before (noted). Call pop() when done
  /// with the file.
  std::optional<lang::FileId> enter(const std::string& name, lang::Span at,
                                    lang::SourceManager& sources, Report& report);
  /// Leaves the innermost file.
  void pop() { chain_.pop_back(); }
  /// Files entered so far (each once), in order, for the outputs a run must not overwrite.
  const std::vector<std::string>& files_read() const { return read_; }

private:
  std::vector<std::string> chain_;                         // canonical paths, outermost first
  std::vector<std::string> read_;                          // as named
  std::vector<std::pair<std::string, std::string>> first_; // canonical path, where it was read
};

} // namespace thermnet::importer
