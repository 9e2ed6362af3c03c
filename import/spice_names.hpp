#pragma once
/// thermnet names for a SPICE netlist's nodes, elements and subcircuits: lower case as SPICE
/// reads them, every character that cannot stand in a name replaced by `_` (a node `x2.a` of a
/// flattened instance is `x2_a`), a leading digit prefixed with `n` (node `1` is `n1`), a
/// statement keyword or built-in name suffixed with `_`.

#include <string>

namespace thermnet::importer::spice {

/// A name made of `text`: allowed characters kept, others `_`, a leading digit prefixed.
std::string sanitize(const std::string& text);

} // namespace thermnet::importer::spice
