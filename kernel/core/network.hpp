#pragma once
/// A thermal network built from a NetworkSpec: unknowns, boundaries, element physics, fixed
/// pattern.

#include "kernel/core/element.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/core/input_check.hpp"
#include "kernel/core/link_batch.hpp"
#include "kernel/core/thermal_system.hpp"
#include "lang/network_spec.hpp"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace thermnet {

/// A spec that cannot be turned into a network (e.g. an element kind no plugin provides).
struct NetworkError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The network the integrators solve: the unknowns are the temperatures of the non-boundary nodes,
/// then the internal states of elements that own some (a thermostat's lagged sensor reading).
class Network final : public ThermalSystem {
public:
  /// Builds the elements from their plugins and fixes the Jacobian pattern.
  explicit Network(lang::NetworkSpec spec,
                   const ElementRegistry& registry = ElementRegistry::global());

  int size() const override { return static_cast<int>(unknown_nodes_.size()) + state_count_; }
  int temperature_count() const override { return static_cast<int>(unknown_nodes_.size()); }
  const std::vector<double>& capacities() const override { return capacities_; }
  void heat_balance(double t, const double* T, double* F) override;
  const SparsityPattern& jacobian_pattern() const override { return pattern_; }
  void jacobian(double t, const double* T, double* values) override;
  int event_count() const override { return event_count_; }
  void events(double t, const double* T, double* g) override;
  bool apply_events(double t, const double* T, const std::vector<int>& fired) override;
  void init_events(double t, const double* T) override;
  std::vector<double> breakpoints(double t0, double t1) const override;
  void explain_failure(double t, double t0, double t1, bool out_of_steps) const override;
  std::string unknown_name(int i) const override;
  std::string event_name(int k) const override;

  /// The spec it was built from.
  const lang::NetworkSpec& spec() const { return spec_; }
  /// Spec node index of each unknown temperature (the first temperature_count() unknowns).
  const std::vector<int>& unknown_nodes() const { return unknown_nodes_; }
  /// The unknowns at t = 0: temperatures T0, else the case's initial, else 20 degC (K), then the
  /// elements' internal states as they start from those temperatures.
  std::vector<double> initial_state() const;
  /// Sets the internal states in x (after its temperature_count() temperatures) to where they
  /// start from those temperatures at t = 0.
  void start_states(std::vector<double>& x) const;
  /// Temperatures of every node, spec order (unknowns from T, boundaries from their signals at
  /// t), K; `all` has one entry per spec node (internal states are not written).
  void expand(double t, const double* T, double* all) const;
  /// Heat entering the network from sources at t, W.
  double source_power(double t, const double* T);
  /// Heat leaving the network into boundaries at t, W.
  double boundary_loss(double t, const double* T);
  /// Heat each element of the spec adds to its terminals at (t, T) (T: all unknowns), W:
  /// heat[e][j] goes into spec().elements[e].nodes[j]; a two-terminal link gives (-Q, +Q) with Q
  /// its flow from the first terminal to the second. `heat` is resized as needed.
  void element_heat(double t, const double* T, std::vector<std::vector<double>>& heat);
  /// Per spec element: 1 when it switches by events (a thermostat), else 0.
  std::vector<char> switching_elements() const;
  /// The reading of sensor spec element e at (t, T) (T: all unknowns), K; throws
  /// std::invalid_argument when e is not a sensor.
  double sensor_reading(std::size_t e, double t, const double* T);
  /// The spec elements that are sensors, in spec order.
  std::vector<int> sensor_elements() const;
  /// True when the heat balance is affine in the unknowns with a constant Jacobian (linear,
  /// time-invariant couplings; inputs may vary in time) and nothing switches by events: then
  /// dT/dt = A T + b(t) with A constant.
  bool affine() const;
  /// affine(), every input linear between breakpoints (no expression of the time), and every
  /// unknown with a capacity (no arithmetic node): what integrate_exact() solves.
  bool piecewise_linear() const override;
  /// piecewise_linear() but with each element's Jacobian constant only between its breakpoints
  /// (Element::jacobian_piecewise_constant()).
  bool piecewise_affine() const override;

private:
  friend class NetworkDerivatives; // differentiates the pieces along parameters

  /// Loads T_all_: every node as expand() does, then the internal states.
  void load(double t, const double* T);
  void stamp_all(double t, const double* T, bool with_jacobian);

  lang::NetworkSpec spec_;
  LinkBatch links_;                                // constant-conductance links, flat
  std::vector<std::unique_ptr<Element>> elements_; // every other element
  std::vector<int> boundary_nodes_;                // spec nodes with prescribed temperatures
  std::vector<int> unknown_nodes_;                 // unknown -> spec node
  std::vector<int> unknown_of_;                    // node array index -> unknown or -1
  int state_count_ = 0;                            // internal states, after the nodes
  std::vector<int> state_owner_;                   // per internal state: index into elements_
  std::vector<std::string> state_names_;           // per internal state: "element.state"
  std::vector<double> capacities_;
  SparsityPattern pattern_;
  /// A built piece of a spec element: a link of links_ (batch >= 0) or an entry of elements_.
  struct Piece {
    int spec_element; ///< index into spec_.elements
    int batch = -1;   ///< index into links_, or -1
    int element = -1; ///< index into elements_, or -1
  };
  std::vector<Piece> pieces_;
  std::vector<std::pair<int, int>> sensors_; // sensors: spec element, index into elements_
  InputCheck inputs_{spec_};                 // expression-valued inputs, checked as time goes
  std::vector<double> F_piece_;              // scratch of element_heat, kept zero between uses
  std::vector<int> event_offset_;            // per element: first event index
  int event_count_ = 0;
  // Scratch sized once: temperatures, heat balance and Jacobian values of every node, then the
  // internal states (node array index spec_.nodes.size() + k holds state k).
  std::vector<double> T_all_, F_all_, J_all_;
  std::vector<double> J_links_; // the links' constant part of J_all_
};

} // namespace thermnet
