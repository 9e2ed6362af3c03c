#pragma once
/// Writes an imported network as thermnet text: its heading, notes and untranslated lines as
/// comments, then consts, submodels, boundaries, nodes, links, heaters, instances and the case;
/// runs of declarations that differ only in an index become index ranges and `for` loops; every
/// statement carries a comment naming the file and line it came from.

#include "import/network.hpp"
#include "import/report.hpp"

#include <string>
#include <vector>

namespace thermnet::importer {

/// The thermnet text of `net`; `remarks` (notes and untranslated lines) are listed in its heading.
std::string write_tnet(const Network& net, const std::vector<Remark>& remarks,
                       const lang::SourceManager& sources);

/// The thermnet text of one submodel definition (its block, origins included).
std::string write_submodel(const Submodel& s, const lang::SourceManager& sources);

} // namespace thermnet::importer
