#pragma once
/// JSON-RPC framing of the language server protocol: `Content-Length: N` headers, then N bytes.

#include <cstddef>
#include <istream>
#include <ostream>
#include <string>

namespace thermnet::lsp {

/// Largest message body accepted (a bigger one is refused as a bad header).
inline constexpr std::size_t max_message_bytes = std::size_t{64} << 20;
/// Deepest nesting of arrays and objects a message may have (a deeper one is refused: its value
/// would be copied and written by recursion).
inline constexpr int max_json_depth = 64;
/// Largest header block kept (its lines together); a longer one is read, dropped and refused.
inline constexpr std::size_t max_header_line_bytes = std::size_t{8} << 10;

/// One message read from the stream.
struct Frame {
  /// What was read.
  enum class Status {
    ok,        ///< a complete body
    eof,       ///< the stream ended (cleanly or inside a message)
    bad_header ///< a header block without a valid Content-Length (its lines were consumed)
  };
  Status status = Status::eof; ///< outcome
  std::string body;            ///< the JSON text (status ok)
  std::string error;           ///< what was wrong (status bad_header)
};

/// Reads the next framed message: header lines up to an empty line, then Content-Length bytes.
Frame read_frame(std::istream& in);

/// Writes one framed message and flushes.
void write_frame(std::ostream& out, const std::string& body);

} // namespace thermnet::lsp
