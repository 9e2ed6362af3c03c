// Element plugin 'thermostat': an on/off heater with hysteresis, switched by root-finding.
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

/// Heats its node with P(t) while on; turns on below T_on and off above T_off (of the sensed node).
class Thermostat final : public Element {
public:
  Thermostat(int node, int sense, lang::Signal P, double on, double off)
      : node_(node), sense_(sense), P_(std::move(P)), on_(on), off_(off) {}
  void declare(JacobianLayout&) override {}
  void stamp(double t, const double*, double* F, double*) const override {
    if (heating_) F[node_] += P_.at(t);
  }
  void breakpoints(std::vector<double>& out) const override {
    out.insert(out.end(), P_.corners().begin(), P_.corners().end());
  }
  int event_count() const override { return 1; }
  /// While off the event is the sensed temperature reaching T_on; while on, reaching T_off.
  void events(double, const double* T, double* g) const override {
    g[0] = T[sense_] - (heating_ ? off_ : on_);
  }
  bool apply_event(int, double, const double*) override {
    heating_ = !heating_;
    return true;
  }
  /// On at or below T_on, off at or above T_off (a start exactly on a switching point would never
  /// cross it); strictly inside the hysteresis band both states are consistent and the present one
  /// is kept (off in a new network; as a steady state with the heater on left it).
  void init_events(double, const double* T) override {
    if (T[sense_] <= on_)
      heating_ = true;
    else if (T[sense_] >= off_)
      heating_ = false;
  }
  double power_in(double t, const double*) const override { return heating_ ? P_.at(t) : 0.0; }

private:
  int node_, sense_;
  lang::Signal P_;
  double on_, off_;
  bool heating_ = false;
};

ElementPlugin make_thermostat() {
  lang::ElementSchema s;
  s.kind = "thermostat";
  s.terminals = 1;
  s.doc = "on/off heater with hysteresis: on below 'on', off above 'off'";
  s.is_source = true;
  s.keys.push_back(Key("P", lang::dim::power, "heating power while on [W], a constant or a signal")
                       .required()
                       .non_negative()
                       .signal());
  s.keys.push_back(Key("on", lang::dim::temperature, "switch-on temperature [degC]")
                       .required()
                       .absolute_temperature());
  s.keys.push_back(Key("off", lang::dim::temperature, "switch-off temperature [degC]")
                       .required()
                       .absolute_temperature());
  s.keys.push_back(
      Key("sense", lang::dim::none, "node whose temperature is sensed (default: the heated node)")
          .node());
  s.check = [](const lang::KeyValues& v) {
    std::vector<lang::KeyProblem> p;
    if (!(v.at("on") < v.at("off")))
      p.push_back({"off", "'off' must be above 'on' (the hysteresis band)"});
    return p;
  };
  return ElementPlugin{std::move(s), [](const lang::ElementSpec& e) -> std::unique_ptr<Element> {
                         auto it = e.node_keys.find("sense");
                         int node = e.nodes.at(0);
                         return std::make_unique<Thermostat>(
                             node, it == e.node_keys.end() ? node : it->second, e.values.at("P"),
                             e.number("on"), e.number("off"));
                       }};
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_thermostat);
} // namespace thermnet
