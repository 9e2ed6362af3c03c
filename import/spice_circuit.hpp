#pragma once
/// A SPICE netlist flattened: subcircuit instances expanded (a node `a` inside instance `x1` is
/// `x1.a`), every value evaluated, and the analysis statements thermnet uses (.tran, .ic, .op).

#include "import/spice_cards.hpp"

#include <map>
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
  /// In an instance: the PWL points as thermnet text in its params (empty: numbers only).
  std::vector<std::pair<std::string, std::string>> pwl_expr;
  std::optional<double> ic;        ///< a capacitor's IC=
  lang::Span at;                   ///< the card
  lang::Span value_at;             ///< the value
  std::size_t scope = 0;           ///< the instance it stands in (0: the top level)
  std::optional<std::string> expr; ///< in an instance: the value as thermnet text in its params
};

/// A parameter of a subcircuit (from its .subckt line) or one of its own .param values.
struct SubcktParam {
  std::string spice;               ///< the SPICE name, lower case
  std::string name;                ///< its thermnet name
  std::optional<std::string> text; ///< thermnet text of its default (or value); none: not written
  bool needs_instance = false;     ///< the default depends on other parameters of the subcircuit
  lang::Span at;                   ///< the definition
};

/// A subcircuit that is instantiated.
struct SubcktDef {
  std::string name;                   ///< SPICE name, lower case
  std::vector<std::string> terminals; ///< its nodes, in order
  std::vector<SubcktParam> params;    ///< parameters of its .subckt line
  std::vector<SubcktParam> locals;    ///< its own .param values
  lang::Span at;                      ///< the .subckt card
};

/// One X card expanded (or the top level, index 0).
struct Instance {
  std::string name;                  ///< the X card's name, lower case (`x1`)
  std::string prefix;                ///< prefix of its flattened names (`x1.x2`)
  std::string subckt;                ///< the subcircuit
  std::size_t parent = 0;            ///< the instance it stands in
  std::vector<std::string> bindings; ///< per terminal, the flattened node it connects to
  /// Parameters the X card gives: thermnet text in the parent's parameters (none: only the
  /// value applies) and the value.
  std::map<std::string, std::pair<std::optional<std::string>, double>> keys;
  std::map<std::string, double> values; ///< every parameter of the subcircuit, evaluated
  lang::Span at;                        ///< the X card
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
  std::string title;                             ///< the title line
  std::vector<Element> elements;                 ///< R, C, I, V elements, in netlist order
  std::optional<Tran> tran;                      ///< .tran, if any
  std::vector<InitialCondition> ics;             ///< .ic settings
  std::optional<lang::Span> op;                  ///< .op, if any
  std::vector<std::string> files;                ///< every file read
  std::vector<Instance> instances;               ///< [0]: the top level; then every X card expanded
  std::vector<SubcktParam> globals;              ///< the netlist's own .param values
  std::map<std::string, SubcktDef> subckts;      ///< the subcircuits instantiated
  std::map<std::string, std::size_t> node_scope; ///< flattened node -> the instance it is in
  std::vector<std::pair<std::string, lang::Span>> unused; ///< subcircuits never instantiated
};

/// Most elements a netlist may expand to (thermnet's own generation limit).
inline constexpr std::size_t max_elements = 5'000'000;

/// Flattens the netlist's cards; problems go to `report`.
Circuit flatten(Netlist netlist, const lang::SourceManager& sources, Report& report);

} // namespace thermnet::importer::spice
