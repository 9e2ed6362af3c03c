#pragma once
/// What an import says besides the model: errors (each at a file, line and column), the lines it
/// did not translate, and notes on what it changed or assumed. Everything goes to a
/// lang::DiagnosticEngine, rendered like every other diagnostic of thermnet.

#include "lang/diagnostics.hpp"

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace thermnet::importer {

/// A problem at a known place in an input file, thrown by the readers' parsers and reported at
/// the line it belongs to (reading goes on with the next line).
struct ImportError : std::runtime_error {
  /// A problem of kind `code` (e.g. "bad-number") at `at`.
  ImportError(lang::Span at, std::string code, const std::string& message);
  lang::Span at;    ///< where
  std::string code; ///< stable code shown in brackets
};

/// Something the model written says about its source: a note, or a line not translated.
struct Remark {
  std::optional<lang::Span> at; ///< where (none: the whole import)
  std::string text;             ///< what
  bool dropped = false;         ///< true: not translated
};

/// Collects an import's errors, untranslated lines and notes.
class Report {
public:
  /// A report into `diags` (its sources hold every file read).
  explicit Report(lang::DiagnosticEngine& diags) : diags_(&diags) {}

  /// Reports an error of kind `code` at `at`, with notes at other places (a first definition).
  void error(lang::Span at, const std::string& code, const std::string& message,
             const std::vector<std::pair<lang::Span, std::string>>& notes = {});
  /// Reports a thrown error.
  void error(const ImportError& e) { error(e.at, e.code, e.what()); }
  /// Reports an error about a file as a whole (no line), naming the file.
  void file_error(const std::string& path, const std::string& code, const std::string& message);
  /// Reports something not translated (a warning `not-translated`; the import fails unless the
  /// user allows a partial model).
  void dropped(lang::Span at, const std::string& what);
  /// Reports a note (`import-note`) that the model's heading repeats.
  void note(std::optional<lang::Span> at, const std::string& text);

  /// True once so many errors were reported that reading should stop.
  bool saturated() const { return diags_->saturated(); }
  /// Errors reported.
  std::size_t error_count() const { return diags_->error_count(); }
  /// Lines (or groups of lines) not translated.
  std::size_t dropped_count() const { return dropped_; }
  /// Notes and untranslated lines, in the order reported.
  const std::vector<Remark>& remarks() const { return remarks_; }
  /// The sources the report's places refer to.
  const lang::SourceManager& sources() const { return diags_->sources(); }

private:
  lang::DiagnosticEngine* diags_;
  std::vector<Remark> remarks_;
  std::size_t dropped_ = 0;
};

/// "file:line" of a place, the file shown safely (for comments in the written model).
std::string place_text(const lang::SourceManager& sources, lang::Span at);

} // namespace thermnet::importer
