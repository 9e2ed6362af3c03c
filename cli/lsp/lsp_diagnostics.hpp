#pragma once
/// The linter's diagnostics as `textDocument/publishDiagnostics` parameters.

#include "cli/lsp/document.hpp"

#include <nlohmann/json.hpp>

namespace thermnet::cli::lsp {

/// `{uri, version, diagnostics}` for a document: problems in the document at their ranges,
/// problems in included files (or without a location) at its first character, named in the text.
nlohmann::json publish_diagnostics_params(const Document& doc);

} // namespace thermnet::cli::lsp
