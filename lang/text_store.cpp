// Text kept in place (lang/text_store.hpp).

#include "lang/text_store.hpp"

#include <algorithm>
#include <cstring>

namespace thermnet::lang {

std::string_view TextStore::keep(std::string_view text) {
  if (text.empty()) return {};
  if (blocks_.empty() || capacity_ - used_ < text.size()) {
    capacity_ = std::max(block_size, text.size());
    blocks_.push_back(std::make_unique_for_overwrite<char[]>(capacity_));
    used_ = 0;
  }
  char* at = blocks_.back().get() + used_;
  std::memcpy(at, text.data(), text.size());
  used_ += text.size();
  return {at, text.size()};
}

} // namespace thermnet::lang
