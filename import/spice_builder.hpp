#pragma once
/// Building the network of a flattened SPICE netlist (used by spice_network.cpp and
/// spice_network_links.cpp): boundaries from V sources, capacities, nodes, resistors, Cauer
/// ladders for Foster chains, heaters and the case.

#include "import/network.hpp"
#include "import/report.hpp"
#include "import/spice_circuit.hpp"
#include "import/spice_foster.hpp"
#include "import/spice_names.hpp"

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace thermnet::importer::spice::detail {

/// A name or node of the netlist, shown safely.
std::string shown(const std::string& s);
/// A plain number as a value.
Value number(double v);
/// A temperature in volts (degC) as a value (kelvin).
Value temperature(double v);
/// A source's value (DC or PWL) as a signal, times `sign`; a temperature for a V source.
Signal signal_of(const Element& e, double sign, bool is_temperature);
/// A flattened node's name as thermnet writes it when every instance is a submodel (`x1.a`;
/// node 0 is `gnd`), for notes.
std::string display(const std::string& flat);
/// The name of Cauer ladder `chain`'s nodes (`kind` "n") or resistors ("r") in the flat network,
/// which the writer of submodels names `cauer_NODE`.
std::string ladder_key(char kind, std::size_t chain, const std::string& driven);

/// Builds the network of a circuit.
class NetworkBuilder {
public:
  /// A builder of `c`'s network; problems go to `report`.
  NetworkBuilder(const Circuit& c, Report& report)
      : c_(c), report_(report), usable_(c.elements.size(), true) {}
  /// The network (incomplete when the report holds errors), named by flattened SPICE names.
  Network build();
  /// Notes each Foster chain written as a Cauer ladder, naming nodes (and ladders, by their
  /// ladder_key) as `name_of` gives their thermnet names.
  void ladder_notes(const std::function<std::string(const std::string&)>& name_of);

private:
  void sources_v();
  void check_elements();
  void capacities();
  void declare_nodes();
  void initial_conditions();
  void resistors();
  void cauer_ladders();
  void heaters();
  void case_spec();
  Name node_name(const std::string& flat);
  std::size_t scope_of(const std::string& flat) const;

  const Circuit& c_;
  Report& report_;
  Network net_;
  std::vector<bool> usable_;
  std::map<std::string, std::size_t> held_;
  std::map<std::string, Signal> held_signal_;
  std::map<std::string, double> cap_;
  std::map<std::string, lang::Span> cap_at_;    // node -> its first capacitor card
  std::map<std::string, std::string> cap_expr_; // node -> its one capacitor's text in its params
  std::map<std::string, int> cap_count_;        // node -> capacitors on it
  std::map<std::string, std::string> cap_from_; // node -> a capacitor of an instance on it
  std::map<std::string, std::pair<double, lang::Span>> t0_;
  std::vector<FosterChain> chains_;
  std::vector<std::pair<std::size_t, std::size_t>> ladders_; // chain, stages: the ladders written
  std::map<std::string, std::size_t> node_index_; // flattened node -> index in net_.nodes
  bool ground_used_ = false;
  lang::Span first_ground_;
};

} // namespace thermnet::importer::spice::detail
