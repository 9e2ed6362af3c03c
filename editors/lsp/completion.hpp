#pragma once
/// `textDocument/completion`: statement keywords and element kinds at a statement's start, keys
/// after a kind, node names in terminal and node-valued positions, params and consts in values.

#include "editors/lsp/document.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>

namespace thermnet::lsp {

/// The CompletionItem list for byte offset `at` (empty when nothing fits).
nlohmann::json completion(const Document& doc, std::size_t at);

} // namespace thermnet::lsp
