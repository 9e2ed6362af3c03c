#pragma once
/// thermnet names for a SPICE netlist's nodes and elements: lower case as SPICE reads them, every
/// character that cannot stand in a name replaced by `_` (a flattened `x1.a` is `x1_a`), a
/// leading digit prefixed with `n` (node `1` is `n1`), made unique within each namespace.

#include "import/network.hpp"

#include <map>
#include <set>
#include <string>

namespace thermnet::importer::spice {

/// The names given so far, per namespace.
class NameMap {
public:
  /// The name of a (flattened) node; the same node always gets the same name.
  Name node(const std::string& flat);
  /// The name of a (flattened) element.
  Name element(const std::string& flat);
  /// A base name for indexed names no other name uses (`cauer_j`, then `cauer_j_2`, ...).
  std::string fresh_base(const std::string& wanted);
  /// The comment for a node: how SPICE names it, when its thermnet name differs ("" otherwise);
  /// `extra` is added (the V source that holds it).
  std::string what(const std::string& flat, const std::string& extra = "");

private:
  std::string unique(const std::string& wanted, std::set<std::string>& used);
  std::map<std::string, std::string> nodes_, elements_;
  std::set<std::string> used_nodes_, used_elements_, bases_;
};

/// A name made of `text`: allowed characters kept, others `_`, a leading digit prefixed.
std::string sanitize(const std::string& text);

} // namespace thermnet::importer::spice
