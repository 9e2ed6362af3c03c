#pragma once
/// The diagnostic engine: every problem of a run is collected here, then rendered as text, JSON or
/// SARIF.

#include "lang/source.hpp"

#include <fmt/format.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace thermnet::lang {

/// How serious a diagnostic is.
enum class Severity { note, warning, error };

/// Identifier of every diagnostic kind (declared as data in diagnostic_kinds.def).
enum class DiagId {
#define DIAG(id, sev, code, fmtstr) id,
#include "lang/diagnostic_kinds.def"
#undef DIAG
};

/// The static description of a diagnostic kind.
struct DiagKind {
  Severity severity;  ///< default severity
  const char* code;   ///< stable code shown in brackets, e.g. "unknown-node"
  const char* format; ///< fmt format string of the message
};

/// The static description of a kind.
const DiagKind& diag_kind(DiagId id);

/// One reported problem, located at `at` (reported line:col) and marking `mark` with the caret.
struct Diagnostic {
  Severity severity = Severity::error; ///< note, warning or error
  std::string code;                    ///< e.g. "unknown-node"
  std::string message;                 ///< the formatted message
  std::optional<Span>
      at; ///< reported location (line:col of at->begin); none for file-less problems
  std::optional<Span> mark; ///< range under the caret (defaults to `at`)
  std::string file_hint;    ///< path to name when `at` is empty (e.g. a file that cannot be read)
  std::vector<Diagnostic> notes; ///< attached notes, rendered after the diagnostic
  bool generated = false;        ///< arose in a loop iteration or instance (notes say which)
};

/// Collects diagnostics of one run; stops accepting errors after a limit so no input floods it.
class DiagnosticEngine {
public:
  /// An engine rendering against the given sources; at most `error_limit` errors are kept.
  explicit DiagnosticEngine(const SourceManager& sources, std::size_t error_limit = 200)
      : sources_(&sources), error_limit_(error_limit) {}

  /// Builds (without reporting) a diagnostic of a kind with message arguments.
  template <typename... Args>
  static Diagnostic make(DiagId id, std::optional<Span> at, std::optional<Span> mark,
                         Args&&... args) {
    const DiagKind& k = diag_kind(id);
    return Diagnostic{k.severity, k.code, fmt::vformat(k.format, fmt::make_format_args(args...)),
                      at,         mark,   {},
                      {},         false};
  }
  /// Reports a diagnostic of a kind with message arguments; returns it so notes can be attached.
  template <typename... Args>
  Diagnostic& report(DiagId id, std::optional<Span> at, std::optional<Span> mark, Args&&... args) {
    return add(make(id, at, mark, std::forward<Args>(args)...));
  }
  /// Builds a note (to push into a diagnostic's notes) of a kind with message arguments.
  template <typename... Args>
  static Diagnostic note(DiagId id, std::optional<Span> at, Args&&... args) {
    const DiagKind& k = diag_kind(id);
    return Diagnostic{Severity::note,
                      k.code,
                      fmt::vformat(k.format, fmt::make_format_args(args...)),
                      at,
                      std::nullopt,
                      {},
                      {},
                      false};
  }
  /// Adds a fully built diagnostic (also used for file-level problems).
  Diagnostic& add(Diagnostic d);

  /// All diagnostics so far, in report order.
  const std::vector<Diagnostic>& all() const { return diags_; }
  /// Number of errors reported.
  std::size_t error_count() const { return errors_; }
  /// Number of warnings reported.
  std::size_t warning_count() const { return warnings_; }
  /// True once the error limit has been reached (callers should stop).
  bool saturated() const { return errors_ >= error_limit_; }
  /// Called by a caller that stops early because the limit was reached: adds the final
  /// too_many_errors diagnostic (once), so the output says that it was cut short.
  void stop_early();
  /// Sorts diagnostics by file, then position (stable for equal positions).
  void sort();
  /// The sources diagnostics refer to.
  const SourceManager& sources() const { return *sources_; }

private:
  const SourceManager* sources_;
  std::size_t error_limit_;
  std::vector<Diagnostic> diags_;
  Diagnostic overflow_sink_;
  std::size_t errors_ = 0;
  std::size_t warnings_ = 0;
};

/// Renders diagnostics compiler-style: "file:line:col: severity: message [code]", source line,
/// caret.
std::string render_text(const DiagnosticEngine& engine, bool color = false);
/// Renders diagnostics as a JSON list of {file, line, column, severity, code, message} (notes
/// included).
std::string render_json(const DiagnosticEngine& engine);
/// Renders diagnostics as a SARIF 2.1.0 log with one run of the tool "thermnet".
std::string render_sarif(const DiagnosticEngine& engine, const std::string& tool_version);

/// The closest candidate to `word` by edit distance, if close enough to be a plausible typo.
std::optional<std::string> closest_match(const std::string& word,
                                         const std::vector<std::string>& candidates);

} // namespace thermnet::lang
