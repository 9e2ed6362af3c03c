#pragma once
/// Appending formatted text to a report being assembled in a buffer.

#include <fmt/format.h>

#include <iterator>
#include <utility>

namespace thermnet::app {

/// Appends `f` formatted with `a` to `out`.
template <class... A> void put(fmt::memory_buffer& out, fmt::format_string<A...> f, A&&... a) {
  fmt::format_to(std::back_inserter(out), f, std::forward<A>(a)...);
}

} // namespace thermnet::app
