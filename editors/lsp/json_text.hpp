#pragma once
/// JSON text written straight into a string, for replies with tens of thousands of items (a
/// document's diagnostics, its symbols) where building a json tree first costs most of the time.
/// The text is the same nlohmann::json::dump() gives (keys must be written in sorted order).

#include <string>
#include <string_view>

namespace thermnet::lsp {

/// Appends `s` as a JSON string literal, escaped as nlohmann::json::dump() escapes it (invalid
/// UTF-8 replaced).
void append_json_string(std::string& out, std::string_view s);

} // namespace thermnet::lsp
