#include "import/network.hpp"

#include <fmt/format.h>

#include <filesystem>

namespace thermnet::importer {

std::string Name::text() const {
  return index ? fmt::format("{}[{}]", base, *index) : base;
}

std::string model_name(const std::string& path, const std::string& prefix) {
  std::string stem = std::filesystem::path(path).stem().string();
  for (char& c : stem)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'))
      c = '_';
  if (stem.empty() || (stem[0] >= '0' && stem[0] <= '9')) stem = prefix + "_" + stem;
  return stem;
}

std::string number_text(double v) {
  if (v == 0) return "0"; // also -0
  return fmt::format("{}", v);
}

} // namespace thermnet::importer
