// Element plugin 'thermostat': an on/off heater with hysteresis, switched by root-finding, with an
// optional first-order sensor lag and optional minimum on and off times.
#include "kernel/core/element_registry.hpp"

#include <limits>

namespace thermnet {
namespace {

/// What a thermostat is built from (SI units; lag and minimum times 0 when absent).
struct ThermostatSettings {
  int node = 0;         ///< heated node
  int sense = 0;        ///< sensed node
  lang::Signal P;       ///< heating power while on, W
  double on = 0.0;      ///< switch-on temperature, K
  double off = 0.0;     ///< switch-off temperature, K
  double lag = 0.0;     ///< sensor time constant, s
  double min_on = 0.0;  ///< least time on after switching on, s
  double min_off = 0.0; ///< least time off after switching off, s
};

/// Heats its node with P(t) while on; turns on below T_on and off above T_off of its reading: the
/// sensed node's temperature, or with a lag the internal state R, dR/dt = (T_sense - R) / lag.
/// With minimum times a second event function, t - (t_switch + min), ends the hold after a
/// switch: crossings of the thresholds during the hold are ignored, and at its end the switch
/// happens if the reading then lies beyond the threshold.
class Thermostat final : public Element {
public:
  explicit Thermostat(ThermostatSettings s) : s_(std::move(s)) {}

  int state_count() const override { return s_.lag > 0.0 ? 1 : 0; }
  void assign_states(int first) override { reading_ = first; }
  /// The sensor starts in equilibrium with the sensed node.
  void initial_states(const double* T, double* x) const override { x[0] = T[s_.sense]; }
  std::string state_name(int) const override { return "sensor"; }
  void declare(JacobianLayout& layout) override {
    if (s_.lag <= 0.0) return;
    self_slot_ = layout.slot(reading_, reading_);
    sense_slot_ = layout.slot(reading_, s_.sense);
  }
  void stamp(double t, const double* T, double* F, double* J) const override {
    if (heating_) F[s_.node] += s_.P.at(t);
    if (s_.lag <= 0.0) return;
    F[reading_] += (T[s_.sense] - T[reading_]) / s_.lag;
    if (!J) return;
    J[self_slot_] -= 1.0 / s_.lag;
    J[sense_slot_] += 1.0 / s_.lag;
  }
  void breakpoints(std::vector<double>& out) const override {
    out.insert(out.end(), s_.P.corners().begin(), s_.P.corners().end());
  }
  int event_count() const override { return holds() ? 2 : 1; }
  /// While off the first event is the reading reaching T_on; while on, reaching T_off. The second
  /// (with minimum times) is the end of the hold after the last switch (positive when none).
  void events(double t, const double* T, double* g) const override {
    g[0] = reading(T) - (heating_ ? s_.off : s_.on);
    if (!holds()) return;
    const double end = hold_end();
    g[1] = end == -kForever ? 1.0 : t - end;
  }
  bool apply_event(int which, double t, const double* T) override {
    if (t < hold_end()) return false; // held: a threshold crossed within a minimum time
    if (which == 0) {
      toggle(t);
      return true;
    }
    // A hold ended: switch now if the reading went beyond the threshold meanwhile.
    const double r = reading(T);
    if (!(heating_ ? r >= s_.off : r <= s_.on)) return false;
    toggle(t);
    return true;
  }
  /// On at or below T_on, off at or above T_off (a start exactly on a switching point would never
  /// cross it); strictly inside the hysteresis band both states are consistent and the present one
  /// is kept (off in a new network; as a steady state with the heater on left it). A switch at or
  /// after t is from an earlier run or the steady-state search (a state held forever) and starts
  /// no hold; a run continued within a hold keeps its state.
  void init_events(double t, const double* T) override {
    if (last_switch_ >= t) last_switch_ = -kForever;
    if (t < hold_end()) return;
    const double r = reading(T);
    if (r <= s_.on)
      heating_ = true;
    else if (r >= s_.off)
      heating_ = false;
  }
  double power_in(double t, const double*) const override { return heating_ ? s_.P.at(t) : 0.0; }

private:
  static constexpr double kForever = std::numeric_limits<double>::infinity();

  /// Whether minimum times are set (the second event function exists).
  bool holds() const { return s_.min_on > 0.0 || s_.min_off > 0.0; }
  /// The temperature the switch acts on, K.
  double reading(const double* T) const { return s_.lag > 0.0 ? T[reading_] : T[s_.sense]; }
  /// When the present state may change at the earliest (-infinity: at any time).
  double hold_end() const {
    const double hold = heating_ ? s_.min_on : s_.min_off;
    return hold > 0.0 ? last_switch_ + hold : -kForever;
  }
  void toggle(double t) {
    heating_ = !heating_;
    last_switch_ = t;
  }

  ThermostatSettings s_;
  int reading_ = -1; // node array index of the lagged reading
  int self_slot_ = 0, sense_slot_ = 0;
  bool heating_ = false;
  double last_switch_ = -kForever;
};

ElementPlugin make_thermostat() {
  lang::ElementSchema s;
  s.kind = "thermostat";
  s.terminals = 1;
  s.doc = "on/off heater with hysteresis: on below 'on', off above 'off'; optional sensor lag "
          "and minimum on/off times";
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
  s.keys.push_back(Key("lag", lang::dim::time,
                       "sensor time constant [s]: the switch acts on R, dR/dt = (T_sense - R) / "
                       "lag (0: no lag)")
                       .otherwise(0.0)
                       .non_negative()
                       .lag());
  s.keys.push_back(Key("min_on", lang::dim::time, "least time on after switching on [s] (0: none)")
                       .otherwise(0.0)
                       .non_negative());
  s.keys.push_back(
      Key("min_off", lang::dim::time, "least time off after switching off [s] (0: none)")
          .otherwise(0.0)
          .non_negative());
  s.check = [](const lang::KeyValues& v) {
    std::vector<lang::KeyProblem> p;
    if (!(v.at("on") < v.at("off")))
      p.push_back({"off", "'off' must be above 'on' (the hysteresis band)"});
    return p;
  };
  return ElementPlugin{std::move(s), [](const lang::ElementSpec& e) -> std::unique_ptr<Element> {
                         ThermostatSettings t;
                         t.node = e.nodes()[0];
                         t.sense = e.node_key("sense").value_or(t.node);
                         t.P = e.values.at("P");
                         t.on = e.number("on");
                         t.off = e.number("off");
                         const auto optional = [&e](const char* key) {
                           return e.has(key) ? e.number(key) : 0.0;
                         };
                         t.lag = optional("lag");
                         if (lang::unresolved_lag(t.lag, std::nullopt)) t.lag = 0.0;
                         t.min_on = optional("min_on");
                         t.min_off = optional("min_off");
                         return std::make_unique<Thermostat>(std::move(t));
                       }};
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_thermostat);
} // namespace thermnet
