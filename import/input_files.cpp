#include "import/input_files.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

namespace thermnet::importer {

namespace fs = std::filesystem;

lang::Span SourceLine::span(std::size_t from, std::size_t to) const {
  const auto at = [&](std::size_t i) {
    return offset + static_cast<std::uint32_t>(std::min(i, text.size()));
  };
  return lang::Span{file, at(from), std::max(at(to), at(from) + (text.empty() ? 0u : 1u))};
}

lang::Span SourceLine::whole() const {
  return span(0, text.size());
}

std::vector<SourceLine> lines_of(const lang::SourceManager& sources, lang::FileId file) {
  const std::string& text = sources.text(file);
  std::vector<SourceLine> lines;
  std::size_t start = 0;
  std::uint32_t number = 1;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::size_t stop = end;
    if (stop > start && text[stop - 1] == '\r') --stop;
    lines.push_back({file, static_cast<std::uint32_t>(start), number++,
                     std::string_view(text).substr(start, stop - start)});
    start = end + 1;
  }
  return lines;
}

InputFileError::InputFileError(const std::string& file, const std::string& why, bool cannot_read)
    : std::runtime_error(
          fmt::format("cannot import '{}': {}", lang::escape_for_display(file), why)),
      path(file), reason(why), unreadable(cannot_read) {}

namespace {

/// Where a binary file shows itself: a NUL byte, or a control character text does not have
/// (tab, line feed, vertical tab, form feed, carriage return and DOS's end-of-file mark are text).
std::optional<std::string> binary_content(const std::string& text) {
  std::size_t line = 1, column = 1;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\n') {
      ++line;
      column = 1;
      continue;
    }
    const bool text_control = c == '\t' || c == '\v' || c == '\f' || c == '\r' || c == 0x1a;
    if ((c < 0x20 && !text_control) || c == 0x7f)
      return fmt::format("it is a binary file, not text (byte 0x{:02X} at line {}, column {})", c,
                         line, column);
    ++column;
  }
  return std::nullopt;
}

std::string canonical(const std::string& path) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? path : c.string();
}

} // namespace

lang::FileId read_input(const std::string& path, lang::SourceManager& sources) {
  if (const long id = sources.find(path); id >= 0) return static_cast<lang::FileId>(id);
  std::string text;
  if (auto problem = lang::read_text_file(path, text)) throw InputFileError(path, *problem, true);
  if (auto problem = binary_content(text)) throw InputFileError(path, *problem, false);
  return sources.add(path, std::move(text));
}

bool IncludeStack::push_root(const std::string& path, Report& report) {
  const std::string key = canonical(path);
  for (const auto& [file, where] : first_)
    if (file == key) {
      report.note(std::nullopt, fmt::format("'{}' was read already ({}): it is read once",
                                            lang::escape_for_display(path), where));
      return false;
    }
  first_.emplace_back(key, "named on the command line");
  chain_.assign(1, key);
  if (std::find(read_.begin(), read_.end(), path) == read_.end()) read_.push_back(path);
  return true;
}

std::optional<lang::FileId> IncludeStack::enter(const std::string& name, lang::Span at,
                                                lang::SourceManager& sources, Report& report) {
  const std::string shown = lang::escape_for_display(name);
  if (name.empty()) {
    report.error(at, "include-unreadable", "the include statement names no file");
    return std::nullopt;
  }
  fs::path target(name);
  if (target.is_relative()) target = fs::path(sources.path(at.file)).parent_path() / target;
  const std::string path = target.lexically_normal().string();
  if (chain_.size() >= max_include_depth) {
    report.error(at, "include-too-deep",
                 fmt::format("cannot include '{}': includes are nested more than {} deep", shown,
                             max_include_depth));
    return std::nullopt;
  }
  const std::string key = canonical(path);
  if (auto cycle = std::find(chain_.begin(), chain_.end(), key); cycle != chain_.end()) {
    std::string route;
    for (auto it = cycle; it != chain_.end(); ++it)
      route += lang::escape_for_display(fs::path(*it).filename().string()) + " -> ";
    report.error(at, "include-cycle",
                 fmt::format("including '{}' again forms a cycle: {}{}", shown, route,
                             lang::escape_for_display(fs::path(key).filename().string())));
    return std::nullopt;
  }
  for (const auto& [file, where] : first_)
    if (file == key) {
      report.note(at, fmt::format("'{}' was read already ({}): it is read once",
                                  lang::escape_for_display(path), where));
      return std::nullopt;
    }
  try {
    const lang::FileId id = read_input(path, sources);
    first_.emplace_back(key, "included at " + place_text(sources, at));
    chain_.push_back(key);
    if (std::find(read_.begin(), read_.end(), path) == read_.end()) read_.push_back(path);
    return id;
  } catch (const InputFileError& e) {
    report.error(at, e.unreadable ? "include-unreadable" : "invalid-encoding",
                 fmt::format("cannot include '{}': {}", lang::escape_for_display(path), e.reason));
    return std::nullopt;
  }
}

} // namespace thermnet::importer
