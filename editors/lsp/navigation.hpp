#pragma once
/// `textDocument/definition` and `textDocument/documentSymbol` from the model's declarations.

#include "editors/lsp/document.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>

namespace thermnet::lsp {

/// The model's name for a name written in the text: itself, else the instance name that ends
/// with `.NAME` (a name inside a submodel), else the first generated `NAME[...]` (an indexed
/// name written with loop variables); empty when nothing matches.
std::string declared_name(const lang::Model& m, const std::string& written);

/// The Location of the declaration of the name at byte offset `at` (node, boundary, param,
/// const, element, case; also in included files), or null.
nlohmann::json definition(const Document& doc, std::size_t at);

/// The DocumentSymbol list of the declarations in the document itself, in text order, as JSON
/// text.
std::string document_symbols_text(const Document& doc);

} // namespace thermnet::lsp
