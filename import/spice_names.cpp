#include "import/spice_names.hpp"

#include <array>

namespace thermnet::importer::spice {

std::string sanitize(const std::string& text) {
  std::string out;
  for (const char c : text)
    out += ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')
               ? c
               : '_';
  if (out.empty() || (out[0] >= '0' && out[0] <= '9')) out = "n" + out;
  static constexpr std::array<const char*, 13> reserved = {
      "model",  "include",  "plugin", "const", "param", "node", "boundary",
      "series", "parallel", "case",   "pi",    "sigma", "gnd"};
  for (const char* r : reserved)
    if (out == r) return out + "_";
  return out;
}

} // namespace thermnet::importer::spice
