#pragma once
/// Document URIs of the protocol versus file paths.

#include <string>

namespace thermnet::lsp {

/// The path of a `file://` URI (percent-decoded); other schemes (e.g. `untitled:`) give a
/// made-up path named after the URI, in the working directory.
std::string uri_to_path(const std::string& uri);

/// The `file://` URI of an absolute path (percent-encoded).
std::string path_to_uri(const std::string& path);

} // namespace thermnet::lsp
