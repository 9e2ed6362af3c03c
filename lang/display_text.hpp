#pragma once
/// Text from files and users made safe to show: what a message echoes (paths, names, excerpts of
/// a file) must not drive a terminal or break an editor's or a JSON reader's UTF-8.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace thermnet::lang {

/// `s` with every byte that is not part of valid UTF-8 shown as <A5> and every control character
/// (C0, DEL, C1) and bidirectional override shown as <U+001B>, as Clang does; the rest unchanged.
std::string escape_for_display(std::string_view s);

/// At most `max_chars` code points of `s` (then "..."), escaped by escape_for_display(): how a
/// message quotes a file it merely references.
std::string excerpt_for_display(std::string_view s, std::size_t max_chars = 40);

} // namespace thermnet::lang
