#pragma once
/// The linter's diagnostics as `textDocument/publishDiagnostics` parameters.

#include "editors/lsp/document.hpp"

#include <string>

namespace thermnet::lsp {

/// The whole `textDocument/publishDiagnostics` notification of a document, as JSON text:
/// problems in the document at their ranges, problems in included files (or without a location)
/// at its first character, named in the text.
std::string publish_diagnostics_message(const Document& doc);

} // namespace thermnet::lsp
