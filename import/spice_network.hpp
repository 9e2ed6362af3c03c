#pragma once
/// A SPICE netlist of a thermal network (volts are degC, amperes are W) as a thermnet network:
/// resistors, capacitors to ground as capacities, V sources to ground as boundaries, I sources as
/// heaters, subcircuits as submodels, Foster chains turned into Cauer ladders, .tran as the case.

#include "import/network.hpp"
#include "import/report.hpp"

#include <functional>
#include <string>
#include <vector>

namespace thermnet::importer::spice {

/// Reads the netlist (the first file; the others as if included) into a network, its
/// subcircuits as submodels (none named after an element kind, which `is_kind` tells); problems
/// go to `report`; `files_read` receives every file read.
Network read_network(const std::vector<std::string>& paths, lang::SourceManager& sources,
                     Report& report, std::vector<std::string>& files_read,
                     const std::function<bool(const std::string&)>& is_kind);

} // namespace thermnet::importer::spice
