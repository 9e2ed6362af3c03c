#pragma once
/// `textDocument/definition` and `textDocument/documentSymbol` from the model's declarations.

#include "cli/lsp/document.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>

namespace thermnet::cli::lsp {

/// The Location of the declaration of the name at byte offset `at` (node, boundary, param,
/// const, element, case; also in included files), or null.
nlohmann::json definition(const Document& doc, std::size_t at);

/// The DocumentSymbol list of the declarations in the document itself, in text order.
nlohmann::json document_symbols(const Document& doc);

} // namespace thermnet::cli::lsp
