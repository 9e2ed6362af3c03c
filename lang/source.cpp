/// Source files of a model: line indexing and offset -> line/column mapping.

#include "lang/source.hpp"

#include "lang/path_policy.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>
#include <unistd.h>

namespace thermnet::lang {

namespace {

constexpr std::size_t kMaxOffset = std::numeric_limits<std::uint32_t>::max();

// Offsets are 32-bit (Span), so line starts beyond 4 GiB cannot be represented; the
// file reader rejects such files long before, this only keeps the index well defined.
std::vector<std::uint32_t> index_lines(const std::string& text) {
  std::vector<std::uint32_t> starts{0};
  const char* data = text.data();
  const std::size_t size = std::min(text.size(), kMaxOffset);

  // Almost every file uses "\n" or "\r\n"; when there is no '\r' at all, memchr over '\n'
  // is several times faster than a byte loop, which matters for 100 MB inputs.
  if (std::memchr(data, '\r', size) == nullptr) {
    const char* p = data;
    const char* end = data + size;
    while (p < end) {
      const void* nl = std::memchr(p, '\n', static_cast<std::size_t>(end - p));
      if (nl == nullptr) break;
      p = static_cast<const char*>(nl) + 1;
      starts.push_back(static_cast<std::uint32_t>(p - data));
    }
    return starts;
  }

  // General case: "\n", "\r\n" and a lone "\r" (classic Mac) all end a line, as in LSP.
  for (std::size_t i = 0; i < size; ++i) {
    const char c = data[i];
    if (c == '\n') {
      starts.push_back(static_cast<std::uint32_t>(i + 1));
    } else if (c == '\r') {
      if (i + 1 < size && data[i + 1] == '\n') ++i;
      starts.push_back(static_cast<std::uint32_t>(i + 1));
    }
  }
  return starts;
}

// Number of UTF-8 code points in [b, e): every byte except continuation bytes (10xxxxxx)
// starts one. A minified model can be one 100 MB line, so this runs eight bytes at a time
// (SWAR): a continuation byte has bit 7 set and bit 6 clear, and per-byte counters are
// folded into a total before any of them can overflow.
std::uint32_t count_code_points(const char* b, const char* e) {
  constexpr std::uint64_t kLowBits = 0x0101010101010101ULL;
  constexpr std::uint64_t kPairs = 0x00FF00FF00FF00FFULL;
  const std::size_t total = static_cast<std::size_t>(e - b);
  std::size_t continuations = 0;
  while (static_cast<std::size_t>(e - b) >= 8) {
    std::uint64_t acc = 0;
    for (int i = 0; i < 255 && static_cast<std::size_t>(e - b) >= 8; ++i, b += 8) {
      std::uint64_t x;
      std::memcpy(&x, b, 8);
      acc += ((x & ~(x << 1)) >> 7) & kLowBits;
    }
    acc = (acc & kPairs) + ((acc >> 8) & kPairs);         // four 16-bit lanes, each <= 510
    continuations += (acc * 0x0001000100010001ULL) >> 48; // sum of the lanes
  }
  for (; b < e; ++b)
    continuations += (static_cast<unsigned char>(*b) & 0xC0) == 0x80;
  return static_cast<std::uint32_t>(total - continuations);
}

// End of the line content starting at `start` and ending before `next` (the next line's
// start, or the end of the text): the terminator ("\n", "\r\n" or "\r") is excluded.
std::size_t content_end(const std::string& text, std::size_t start, std::size_t next) {
  std::size_t end = next;
  if (end > start && text[end - 1] == '\n') --end;
  if (end > start && text[end - 1] == '\r') --end;
  return end;
}

} // namespace

std::optional<std::string> read_text_file(const std::string& path, std::string& text) {
  int fd = -1;
  std::size_t size = 0;
  if (auto problem = open_model_file(path, max_file_bytes, fd, size)) return problem;
  // A regular file whose size fstat knows: read that much and one byte more, which finds the end
  // without growing the string (and stop at the limit should the file grow).
  text.clear();
  text.resize(size + 1);
  std::size_t got = 0;
  for (;;) {
    if (got == text.size()) {
      if (text.size() > max_file_bytes) break;
      text.resize(std::min(text.size() + (std::size_t{1} << 20), max_file_bytes + 1));
    }
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      text.clear();
      return std::string(std::strerror(err));
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  text.resize(got);
  if (text.size() > max_file_bytes) {
    text.clear();
    return "it is larger than 1 GiB";
  }
  return std::nullopt;
}

FileId SourceManager::add(std::string path, std::string text) {
  File f;
  f.line_starts = index_lines(text);
  f.path = std::move(path);
  f.text = std::move(text);
  files_.push_back(std::move(f));
  return static_cast<FileId>(files_.size() - 1);
}

LineCol SourceManager::line_col(FileId id, std::uint32_t offset) const {
  const File& f = files_.at(id);
  const std::size_t off = std::min<std::size_t>(offset, f.text.size());
  // The last line start not after `off`; line_starts[0] == 0, so the iterator is never begin().
  const auto it = std::upper_bound(f.line_starts.begin(), f.line_starts.end(), off);
  const std::size_t line = static_cast<std::size_t>(it - f.line_starts.begin());
  const std::size_t start = f.line_starts[line - 1];
  const std::size_t next = it == f.line_starts.end() ? f.text.size() : *it;
  // An offset inside the terminator (e.g. the '\n' of "\r\n") maps to just past the
  // line's last character, the same column as in a "\n" file.
  const std::size_t stop = std::min(off, content_end(f.text, start, next));
  const std::uint32_t col = count_code_points(f.text.data() + start, f.text.data() + stop) + 1;
  return LineCol{static_cast<std::uint32_t>(line), col};
}

std::string_view SourceManager::line_text(FileId id, std::uint32_t line) const {
  const File& f = files_.at(id);
  if (line == 0 || line > f.line_starts.size()) return {};
  const std::size_t start = f.line_starts[line - 1];
  const std::size_t next = line < f.line_starts.size() ? f.line_starts[line] : f.text.size();
  return std::string_view(f.text).substr(start, content_end(f.text, start, next) - start);
}

long SourceManager::find(const std::string& path) const {
  for (std::size_t i = 0; i < files_.size(); ++i)
    if (files_[i].path == path) return static_cast<long>(i);
  return -1;
}

} // namespace thermnet::lang
