#pragma once
/// The CSV files a model reads (`table(...)`, `data`), parsed once per file and layout and shared
/// by every elaboration of the model (a calibration elaborates it thousands of times).

#include "lang/csv.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

namespace thermnet::lang {

/// Parsed CSV files by path and layout; thread-safe.
class TableCache {
public:
  /// The table of a file read with a layout, parsed on first use; throws CsvError (a failure is
  /// not kept: the next call reads the file again).
  std::shared_ptr<const CsvTable> get(const std::string& path, const CsvLayout& layout);

private:
  std::mutex mutex_;
  std::map<std::pair<std::string, CsvLayout>, std::shared_ptr<const CsvTable>> tables_;
};

} // namespace thermnet::lang
