#include "import/spice_names.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

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

std::string NameMap::unique(const std::string& wanted, std::set<std::string>& used) {
  std::string name = wanted;
  for (int k = 2; !used.insert(name).second; ++k)
    name = fmt::format("{}_{}", wanted, k);
  return name;
}

Name NameMap::node(const std::string& flat) {
  auto it = nodes_.find(flat);
  if (it == nodes_.end()) it = nodes_.emplace(flat, unique(sanitize(flat), used_nodes_)).first;
  return Name{it->second, {}};
}

Name NameMap::element(const std::string& flat) {
  auto it = elements_.find(flat);
  if (it == elements_.end())
    it = elements_.emplace(flat, unique(sanitize(flat), used_elements_)).first;
  return Name{it->second, {}};
}

std::string NameMap::fresh_base(const std::string& wanted) {
  std::string base = wanted;
  for (int k = 2;
       used_nodes_.count(base) || used_elements_.count(base) || !bases_.insert(base).second; ++k)
    base = fmt::format("{}_{}", wanted, k);
  return base;
}

std::string NameMap::what(const std::string& flat, const std::string& extra) {
  std::string text;
  if (node(flat).base != flat) text = "SPICE node " + lang::excerpt_for_display(flat, 60);
  if (!extra.empty())
    text +=
        (text.empty() ? "" : ", ") + std::string("held by ") + lang::excerpt_for_display(extra, 60);
  return text;
}

} // namespace thermnet::importer::spice
