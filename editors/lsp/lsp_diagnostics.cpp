#include "editors/lsp/lsp_diagnostics.hpp"

#include "editors/lsp/json_text.hpp"
#include "editors/lsp/position.hpp"
#include "editors/lsp/uri.hpp"
#include "lang/display_text.hpp"

#include <fmt/format.h>

namespace thermnet::lsp {
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

/// Appends one diagnostic in protocol form (its keys in the order json's dump() sorts them).
void append_diagnostic(std::string& out, const Document& doc, const lang::Diagnostic& d) {
  const auto& sources = doc.sources();
  std::string message = lang::escape_for_display(d.message);
  std::string range;
  if (d.at && d.at->file == doc.root()) {
    lang::Span s = d.mark && d.mark->file == doc.root() ? *d.mark : *d.at;
    doc.lines().append_range(range, s.begin, s.end);
  } else {
    doc.lines().append_range(range, 0, 0);
    if (d.at) {
      lang::LineCol lc = sources.line_col(d.at->file, d.at->begin);
      message = lang::escape_for_display(
          fmt::format("{}:{}:{}: {}", sources.path(d.at->file), lc.line, lc.column, d.message));
    } else if (!d.file_hint.empty()) {
      message = lang::escape_for_display(fmt::format("{}: {}", d.file_hint, d.message));
    }
  }
  std::string related;
  for (const auto& n : d.notes)
    if (n.at) {
      related += related.empty() ? "{\"location\":" : ",{\"location\":";
      related +=
          location_json(doc, *n.at).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
      related += ",\"message\":";
      append_json_string(related, lang::escape_for_display(n.message));
      related += '}';
    } else {
      message += "\nnote: " + lang::escape_for_display(n.message);
    }
  out += "{\"code\":";
  append_json_string(out, d.code);
  out += ",\"message\":";
  append_json_string(out, message);
  out += ",\"range\":";
  out += range;
  if (!related.empty()) {
    out += ",\"relatedInformation\":[";
    out += related;
    out += ']';
  }
  out += ",\"severity\":";
  out += std::to_string(severity_code(d.severity));
  out += ",\"source\":\"thermnet\"}";
}

} // namespace

std::string publish_diagnostics_message(const Document& doc) {
  std::string out = R"({"jsonrpc":"2.0","method":"textDocument/publishDiagnostics","params":{)"
                    R"("diagnostics":[)";
  out.reserve(doc.diagnostics().all().size() * 250); // a diagnostic takes about 200 bytes
  bool first = true;
  for (const auto& d : doc.diagnostics().all()) {
    if (!first) out += ',';
    first = false;
    append_diagnostic(out, doc, d);
  }
  out += "],\"uri\":";
  append_json_string(out, doc.uri());
  out += ",\"version\":";
  out += std::to_string(doc.version());
  out += "}}";
  return out;
}

} // namespace thermnet::lsp
