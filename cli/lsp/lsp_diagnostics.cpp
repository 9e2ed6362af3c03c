#include "cli/lsp/lsp_diagnostics.hpp"

#include "cli/lsp/position.hpp"
#include "cli/lsp/uri.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

namespace thermnet::cli::lsp {
namespace {

/// LSP DiagnosticSeverity of a severity.
int severity_code(lang::Severity s) {
  switch (s) {
  case lang::Severity::error:
    return 1;
  case lang::Severity::warning:
    return 2;
  case lang::Severity::note:
    return 3;
  }
  return 1;
}

/// A location `{uri, range}` of a span (the document's own URI for its own spans).
nlohmann::json location_json(const Document& doc, const lang::Span& span) {
  const auto& sources = doc.sources();
  std::string uri = span.file == doc.root() ? doc.uri() : path_to_uri(sources.path(span.file));
  return {{"uri", uri}, {"range", range_json(sources.text(span.file), span.begin, span.end)}};
}

/// One diagnostic in protocol form.
nlohmann::json diagnostic_json(const Document& doc, const lang::Diagnostic& d) {
  const auto& sources = doc.sources();
  nlohmann::json out = {{"severity", severity_code(d.severity)},
                        {"code", d.code},
                        {"source", "thermnet"},
                        {"message", lang::escape_for_display(d.message)}};
  if (d.at && d.at->file == doc.root()) {
    lang::Span s = d.mark && d.mark->file == doc.root() ? *d.mark : *d.at;
    out["range"] = doc.lines().range(s.begin, s.end);
  } else {
    out["range"] = doc.lines().range(0, 0);
    if (d.at) {
      lang::LineCol lc = sources.line_col(d.at->file, d.at->begin);
      out["message"] = lang::escape_for_display(
          fmt::format("{}:{}:{}: {}", sources.path(d.at->file), lc.line, lc.column, d.message));
    } else if (!d.file_hint.empty()) {
      out["message"] = lang::escape_for_display(fmt::format("{}: {}", d.file_hint, d.message));
    }
  }
  nlohmann::json related = nlohmann::json::array();
  for (const auto& n : d.notes)
    if (n.at)
      related.push_back({{"location", location_json(doc, *n.at)},
                         {"message", lang::escape_for_display(n.message)}});
    else
      out["message"] =
          out["message"].get<std::string>() + "\nnote: " + lang::escape_for_display(n.message);
  if (!related.empty()) out["relatedInformation"] = related;
  return out;
}

} // namespace

nlohmann::json publish_diagnostics_params(const Document& doc) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& d : doc.diagnostics().all())
    list.push_back(diagnostic_json(doc, d));
  return {{"uri", doc.uri()}, {"version", doc.version()}, {"diagnostics", list}};
}

} // namespace thermnet::cli::lsp
