#pragma once
/// Lists of node names on a command line: names of generated nodes hold commas (`p[3,7]`).

#include <string>
#include <vector>

namespace thermnet::lang {

/// Joins back the pieces of names that splitting a list at every comma cut inside square
/// brackets: {"p[1", "2]", "q"} -> {"p[1,2]", "q"}.
std::vector<std::string> join_bracketed(const std::vector<std::string>& pieces);

} // namespace thermnet::lang
