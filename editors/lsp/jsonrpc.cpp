#include "editors/lsp/jsonrpc.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>

#include <fmt/format.h>

namespace thermnet::lsp {
namespace {

/// Lower-case copy, for the case-insensitive header name.
std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// Trims spaces and tabs at both ends.
std::string trim(const std::string& s) {
  std::size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  std::size_t e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

/// Reads one line up to '\n' into `line`, keeping at most max_header_line_bytes of it (the rest is
/// read and dropped, so a huge line costs no memory); false at the end of the input.
bool read_header_line(std::istream& in, std::string& line, bool& too_long) {
  line.clear();
  too_long = false;
  for (int c = in.get(); c != std::char_traits<char>::eof(); c = in.get()) {
    if (c == '\n') return true;
    if (line.size() < max_header_line_bytes)
      line += static_cast<char>(c);
    else
      too_long = true;
  }
  return !line.empty() || too_long;
}

} // namespace

Frame read_frame(std::istream& in) {
  Frame f;
  std::string line;
  bool any_header = false;
  bool have_length = false;
  std::size_t length = 0;
  std::string problem;
  std::size_t header_bytes = 0;
  while (true) {
    bool too_long = false;
    if (!read_header_line(in, line, too_long)) return f; // eof, possibly inside a header block
    if (!line.empty() && line.back() == '\r') line.pop_back();
    header_bytes += line.size();
    if (too_long || header_bytes > max_header_line_bytes) {
      problem = fmt::format("a header longer than {} bytes", max_header_line_bytes);
      if (too_long) { // only its first bytes were kept: nothing to parse
        any_header = true;
        continue;
      }
    }
    if (line.empty()) {
      if (!any_header) continue; // stray blank lines between messages
      break;
    }
    any_header = true;
    std::size_t colon = line.find(':');
    if (colon == std::string::npos) {
      problem = "a header line without ':'";
      continue;
    }
    if (lower(trim(line.substr(0, colon))) != "content-length") continue;
    std::string value = trim(line.substr(colon + 1));
    auto [p, ec] = std::from_chars(value.data(), value.data() + value.size(), length);
    if (ec != std::errc() || p != value.data() + value.size()) {
      problem = "Content-Length is not a number";
      continue;
    }
    have_length = true;
  }
  if (!have_length || !problem.empty() || length > max_message_bytes) {
    f.status = Frame::Status::bad_header;
    f.error = !problem.empty() ? problem
              : !have_length   ? std::string("no Content-Length header")
                             : fmt::format("message too large ({} bytes; the limit is {})", length,
                                           max_message_bytes);
    // Skip the body of a framed message (too large, or with a header too long), unkept.
    if (have_length) in.ignore(static_cast<std::streamsize>(length));
    return f;
  }
  f.body.resize(length);
  in.read(f.body.data(), static_cast<std::streamsize>(length));
  if (static_cast<std::size_t>(in.gcount()) != length) {
    f.body.clear();
    return f; // eof inside the body
  }
  f.status = Frame::Status::ok;
  return f;
}

void write_frame(std::ostream& out, const std::string& body) {
  out << "Content-Length: " << body.size() << "\r\n\r\n" << body;
  out.flush();
}

} // namespace thermnet::lsp
