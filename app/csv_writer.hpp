#pragma once
/// The one way every output writes CSV text: fields quoted where a CSV reader needs it (a comma
/// in `p[3,7]`, a quote, a line break), so each row has as many fields as its header.

#include <fmt/format.h>

#include <string>
#include <string_view>
#include <vector>

namespace thermnet::app {

/// Appends a field: as it is, or quoted (`"p[3,7]"`, inner quotes doubled) when it holds a comma, a
/// quote or a line break.
void append_csv_field(fmt::memory_buffer& out, std::string_view field);

/// One line of fields separated by commas, each appended by append_csv_field, ending in '\n'.
std::string csv_line(const std::vector<std::string>& fields);

} // namespace thermnet::app
