#include "import/report.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

namespace thermnet::importer {

ImportError::ImportError(lang::Span where, std::string kind, const std::string& message)
    : std::runtime_error(message), at(where), code(std::move(kind)) {}

namespace {

lang::Diagnostic make(lang::Severity severity, std::optional<lang::Span> at, std::string code,
                      std::string message) {
  lang::Diagnostic d;
  d.severity = severity;
  d.code = std::move(code);
  d.message = std::move(message);
  d.at = at;
  d.mark = at;
  return d;
}

} // namespace

void Report::error(lang::Span at, const std::string& code, const std::string& message,
                   const std::vector<std::pair<lang::Span, std::string>>& notes) {
  lang::Diagnostic d = make(lang::Severity::error, at, code, message);
  for (const auto& [where, text] : notes) {
    lang::Diagnostic n = make(lang::Severity::note, where, code, text);
    n.mark = std::nullopt;
    d.notes.push_back(std::move(n));
  }
  diags_->add(std::move(d));
}

void Report::file_error(const std::string& path, const std::string& code,
                        const std::string& message) {
  lang::Diagnostic d = make(lang::Severity::error, std::nullopt, code, message);
  d.file_hint = path;
  diags_->add(std::move(d));
}

void Report::dropped(lang::Span at, const std::string& what) {
  ++dropped_;
  remarks_.push_back({at, what, true});
  diags_->add(make(lang::Severity::warning, at, "not-translated", "not translated: " + what));
}

void Report::note(std::optional<lang::Span> at, const std::string& text) {
  remarks_.push_back({at, text, false});
  diags_->add(make(lang::Severity::note, at, "import-note", text));
}

std::string place_text(const lang::SourceManager& sources, lang::Span at) {
  return fmt::format("{}:{}", lang::escape_for_display(sources.path(at.file)),
                     sources.line_col(at.file, at.begin).line);
}

} // namespace thermnet::importer
