#pragma once
/// `textDocument/hover`: element kinds, keys and declared names under the cursor.

#include "editors/lsp/document.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>

namespace thermnet::lsp {

/// The Hover result at byte offset `at` (markdown contents and the word's range), or null.
nlohmann::json hover(const Document& doc, std::size_t at);

} // namespace thermnet::lsp
