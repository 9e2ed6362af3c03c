#pragma once
/// Text kept in place for the life of its owner: generated names are copied here once and viewed
/// from the declarations, without a string object per name.

#include <cstddef>
#include <memory>
#include <string_view>
#include <vector>

namespace thermnet::lang {

/// Appends texts into blocks that never move; a view returned by keep() stays valid until the
/// store is destroyed.
class TextStore {
public:
  /// A copy of `text` kept in the store.
  std::string_view keep(std::string_view text);

private:
  static constexpr std::size_t block_size = 64 * 1024;
  std::vector<std::unique_ptr<char[]>> blocks_;
  std::size_t used_ = 0;     // bytes used in the last block
  std::size_t capacity_ = 0; // size of the last block
};

} // namespace thermnet::lang
