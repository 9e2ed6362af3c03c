#pragma once
/// Foster chains in a flattened SPICE netlist: capacitors between two nodes neither of which is
/// ground, each with resistors across it (a cell), in series through inner nodes that touch
/// nothing else. A chain whose last node holds only a resistor and a capacitor to ground is
/// extended to ground by that cell. Each chain's driven end is the end that is not held (ground
/// or a V source), or the end a current source heats.

#include "import/foster_cauer.hpp"
#include "import/report.hpp"
#include "import/spice_circuit.hpp"

#include <functional>
#include <set>
#include <string>
#include <vector>

namespace thermnet::importer::spice {

/// A Foster chain found in the netlist.
struct FosterChain {
  std::string driven;                ///< the driven end (a flattened node)
  std::string far;                   ///< the other end ("0": ground)
  bool far_held = false;             ///< the far end is ground or held by a V source
  std::vector<std::string> inner;    ///< the inner nodes, driven end first (they vanish)
  std::vector<FosterCell> cells;     ///< the cells, driven end first
  std::vector<std::size_t> consumed; ///< the elements the chain is made of
  lang::Span at;                     ///< its first capacitor's card
  bool written = true;               ///< false: it joins two held nodes and is left out
};

/// Finds the Foster chains among the `usable` elements; every capacitor between two non-ground
/// nodes must belong to one, else an error at its card says why not. `held` tells ground and
/// nodes held by V sources; `with_ic` the nodes an .ic names.
std::vector<FosterChain> find_foster_chains(const std::vector<Element>& elements,
                                            const std::vector<bool>& usable,
                                            const std::function<bool(const std::string&)>& held,
                                            const std::set<std::string>& with_ic, Report& report);

} // namespace thermnet::importer::spice
