#include "import/network.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <unordered_map>
#include <vector>

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

// (SPICE has no DC path to ground in such a part; its temperatures in a transient are still
// defined.)
void note_floating(const Network& net, Report& report,
                   const std::function<std::string(const Name&)>& shown) {
  std::unordered_map<std::string, std::size_t> index; // node, then boundary names -> 0, 1, ...
  for (const Node& n : net.nodes)
    index.emplace(n.name.text(), index.size());
  for (const Boundary& b : net.boundaries)
    index.emplace(b.name.text(), index.size());
  std::vector<std::size_t> parent(index.size());
  for (std::size_t k = 0; k < parent.size(); ++k)
    parent[k] = k;
  const auto root = [&parent](std::size_t k) { // (path halving: a million-node chain stays fast)
    while (parent[k] != k)
      k = parent[k] = parent[parent[k]];
    return k;
  };
  for (const Link& l : net.links) {
    const auto a = index.find(l.a.text()), b = index.find(l.b.text());
    if (a != index.end() && b != index.end()) parent[root(a->second)] = root(b->second);
  }
  std::vector<char> anchored(parent.size(), 0);
  for (const Boundary& b : net.boundaries)
    anchored[root(index.at(b.name.text()))] = 1;
  for (std::size_t k = 0; k < net.nodes.size(); ++k)
    if (!anchored[root(k)])
      report.note(net.nodes[k].origin,
                  fmt::format("node {} has no path of links to a boundary (a floating part: no DC "
                              "path to ground in SPICE): its steady state is undetermined, and "
                              "lint warns of it",
                              shown(net.nodes[k].name)));
}

} // namespace thermnet::importer
