#pragma once
/// SPICE subcircuits as thermnet submodels: the flattened network's parts are grouped by the
/// instance they stand in, and each subcircuit is written once, as a submodel (its .subckt
/// parameters its params, its own .param values its consts, node 0 a terminal `gnd`), its X cards
/// as instance statements. A subcircuit whose instances do not all come out the same (a value its
/// parameters cannot express, a Foster chain converted to different Cauer ladders, a chain that
/// crosses its boundary) is flattened into the part that holds it, and the report says why.

#include "import/network.hpp"
#include "import/report.hpp"
#include "import/spice_circuit.hpp"

#include <functional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace thermnet::importer::spice {

/// What fold() gives.
struct Folded {
  Network net;                                           ///< the network with its submodels
  std::vector<std::pair<lang::Span, std::string>> notes; ///< notes on the subcircuits
  std::vector<std::string> prefix; ///< per instance, its names' prefix (`x1.`; flattened: "")
  /// Per flattened node (and Cauer ladder, by its key): the instance it is written in, its name.
  std::unordered_map<std::string, std::pair<std::size_t, std::string>> local;
  /// The full thermnet name of a flattened node or ladder (`x1.surf`; node 0 is `gnd`).
  std::string name(const std::string& flat) const;
};

/// `flat` (the network of the flattened circuit `c`, named by flattened SPICE names) with its
/// subcircuits as submodels and every name a thermnet name; `is_kind` tells the element kinds a
/// submodel may not be named after; `sources` holds the files.
Folded fold(const Network& flat, const Circuit& c, const lang::SourceManager& sources,
            const std::function<bool(const std::string&)>& is_kind);

} // namespace thermnet::importer::spice
