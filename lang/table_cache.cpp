#include "lang/table_cache.hpp"

namespace thermnet::lang {

std::shared_ptr<const CsvTable> TableCache::get(const std::string& path, const CsvLayout& layout) {
  std::lock_guard lock(mutex_);
  auto key = std::make_pair(path, layout);
  if (auto it = tables_.find(key); it != tables_.end()) return it->second;
  // Parsed under the lock: elaborations of one model in parallel wait for the first reader
  // instead of reading the same file each.
  auto table = std::make_shared<const CsvTable>(read_csv(path, layout));
  tables_.emplace(std::move(key), table);
  return table;
}

} // namespace thermnet::lang
