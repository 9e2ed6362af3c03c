#pragma once
/// A SPICE netlist flattened: subcircuit instances expanded (a node `a` inside instance `x1` is
/// `x1.a`), every value evaluated, and the analysis statements thermnet uses (.tran, .ic, .op).

#include "import/spice_cards.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace thermnet::importer::spice {

/// One R, C, I or V element of the flattened netlist.
struct Element {
  char kind = 'r';                            ///< 'r', 'c', 'i' or 'v'
  std::string name;                           ///< flattened name, lower case (`x1.r1`)
  std::string a;                              ///< first node, flattened ("0": ground)
  std::string b;                              ///< second node, flattened
  double value = 0;                           ///< R, C, or the DC value of a source
  std::vector<std::pair<double, double>> pwl; ///< a source's PWL points (time, value)
  std::optional<double> ic;                   ///< a capacitor's IC=
  lang::Span at;                              ///< the card
  lang::Span value_at;                        ///< the value
};

/// The .tran statement.
struct Tran {
  double step = 0;  ///< TSTEP: output interval
  double stop = 0;  ///< TSTOP: end time
  double start = 0; ///< TSTART: first output time
  bool uic = false; ///< UIC: start from the initial conditions, not the operating point
  lang::Span at;    ///< where
};

/// A `.ic V(node) = value`.
struct InitialCondition {
  std::string node; ///< flattened node
  double value = 0; ///< its voltage (temperature)
  lang::Span at;    ///< where
};

/// The flattened netlist.
struct Circuit {
  std::string title;                 ///< the title line
  std::vector<Element> elements;     ///< R, C, I, V elements, in netlist order
  std::optional<Tran> tran;          ///< .tran, if any
  std::vector<InitialCondition> ics; ///< .ic settings
  std::optional<lang::Span> op;      ///< .op, if any
  std::vector<std::string> files;    ///< every file read
};

/// Most elements a netlist may expand to (thermnet's own generation limit).
inline constexpr std::size_t max_elements = 5'000'000;

/// Flattens the netlist's cards; problems go to `report`.
Circuit flatten(Netlist netlist, const lang::SourceManager& sources, Report& report);

} // namespace thermnet::importer::spice
