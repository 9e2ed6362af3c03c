// Element plugin 'sensor': how a node (or the mean of several) is measured — a first-order lag,
// an offset and a gain. It carries no heat; a measured series of its node is compared with its
// reading.
#include "kernel/core/element_registry.hpp"

#include "lang/units.hpp"

#include <numeric>

namespace thermnet {
namespace {

/// Reads the mean temperature of its nodes through a lag: R' = (mean T - R) / tau (R = mean T
/// without a lag); its reading is offset + gain * R in degC, returned in K.
class Sensor final : public Element {
public:
  Sensor(std::vector<int> nodes, double tau, double offset, double gain)
      : nodes_(std::move(nodes)), tau_(lang::unresolved_lag(tau, std::nullopt) ? 0.0 : tau),
        offset_(offset), gain_(gain) {}

  int state_count() const override { return tau_ > 0.0 ? 1 : 0; }
  void assign_states(int first) override { state_ = first; }
  /// The lagged reading starts in equilibrium with its nodes.
  void initial_states(const double* T, double* x) const override { x[0] = mean(T); }
  std::string state_name(int) const override { return "reading"; }
  bool affine() const override { return true; }
  void declare(JacobianLayout& layout) override {
    if (tau_ <= 0.0) return;
    // declare() runs twice (the network records the pattern, then hands out the slots): the
    // slots of the last call are the ones kept.
    self_slot_ = layout.slot(state_, state_);
    node_slots_.clear();
    for (int n : nodes_)
      node_slots_.push_back(layout.slot(state_, n));
  }
  void stamp(double, const double* T, double* F, double* J) const override {
    if (tau_ <= 0.0) return;
    F[state_] += (mean(T) - T[state_]) / tau_;
    if (!J) return;
    J[self_slot_] -= 1.0 / tau_;
    const double w = 1.0 / (tau_ * static_cast<double>(nodes_.size()));
    for (int slot : node_slots_)
      J[slot] += w;
  }
  std::optional<double> sensor_reading(const double* T) const override {
    const double r = tau_ > 0.0 ? T[state_] : mean(T);
    return offset_ + gain_ * (r - lang::kZeroCelsius) + lang::kZeroCelsius;
  }

private:
  double mean(const double* T) const {
    double sum = 0.0;
    for (int n : nodes_)
      sum += T[n];
    return sum / static_cast<double>(nodes_.size());
  }

  std::vector<int> nodes_;
  double tau_, offset_, gain_;
  int state_ = 0;
  int self_slot_ = 0;
  std::vector<int> node_slots_;
};

ElementPlugin make_sensor() {
  lang::ElementSchema s;
  s.kind = "sensor";
  s.terminals = 1;
  s.observes = true;
  s.doc = "how a node, or the mean of several (sensor s mean(a, b)), is measured: a first-order "
          "lag, an offset and a gain; carries no heat";
  s.keys.push_back(Key("tau", lang::dim::time, "time constant of the first-order lag [s] (0: none)")
                       .otherwise(0.0)
                       .non_negative()
                       .lag());
  s.keys.push_back(Key("offset", lang::dim::temperature,
                       "constant added to the reading [K] (a temperature difference)")
                       .otherwise(0.0)
                       .temperature_difference());
  s.keys.push_back(Key("gain", lang::Dimension{}, "factor on the reading in degC (1: none)")
                       .otherwise(1.0)
                       .positive());
  return ElementPlugin{std::move(s), [](const lang::ElementSpec& e) -> std::unique_ptr<Element> {
                         const auto nodes = e.nodes();
                         return std::make_unique<Sensor>(
                             std::vector<int>(nodes.begin(), nodes.end()), e.number("tau"),
                             e.number("offset"), e.number("gain"));
                       }};
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_sensor);
} // namespace thermnet
