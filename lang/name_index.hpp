#pragma once
/// The map from a declared name to its declaration's index. A generated model declares hundreds
/// of thousands of names and every element looks its terminals up, so the map is open-addressed
/// (tsl::robin_map, hashes stored beside the keys): a lookup reads one bucket array instead of a
/// linked node per entry.

#include <tsl/robin_map.h>

#include <functional>
#include <memory>
#include <string_view>
#include <utility>

namespace thermnet::lang {

/// Declared name (a view of the declaration's own string) -> index of the declaration.
using NameIndex = tsl::robin_map<std::string_view, int, std::hash<std::string_view>,
                                 std::equal_to<std::string_view>,
                                 std::allocator<std::pair<std::string_view, int>>,
                                 /*StoreHash=*/true>;

} // namespace thermnet::lang
