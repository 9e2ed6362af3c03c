// Example plugin: a Peltier (thermoelectric) element between a cold and a hot node.
//
// With Seebeck coefficient S, current I, electrical resistance R and thermal conductance K:
//   heat taken from the cold node    Qc = S I Tc - I^2 R / 2 - K (Th - Tc)
//   heat delivered to the hot node   Qh = S I Th + I^2 R / 2 - K (Th - Tc)
// The difference Qh - Qc = S I (Th - Tc) + I^2 R is the electrical power it consumes.
#include "kernel/plugin_host/plugin_api.hpp"

namespace {

using thermnet::Element;
using thermnet::JacobianLayout;
using thermnet::Key;

namespace dim = thermnet::lang::dim;
constexpr thermnet::lang::Dimension current{{0, 0, 0, 0, 1, 0, 0}}; // A
constexpr thermnet::lang::Dimension voltage = dim::power / current; // V
constexpr thermnet::lang::Dimension seebeck = voltage / dim::temperature;
constexpr thermnet::lang::Dimension ohm = voltage / current;

/// The element: a heat pump from its first terminal (cold side) to its second (hot side).
class Peltier final : public Element {
public:
  Peltier(int cold, int hot, double S, thermnet::lang::Signal I, double R, double K)
      : c_(cold), h_(hot), S_(S), I_(std::move(I)), R_(R), K_(K) {}

  void declare(JacobianLayout& layout) override { thermnet::declare_link(layout, c_, h_, slots_); }

  void stamp(double t, const double* T, double* F, double* J) const override {
    const double I = I_.at(t);
    const double leak = K_ * (T[h_] - T[c_]);
    const double joule = 0.5 * I * I * R_;
    F[c_] -= S_ * I * T[c_] - joule - leak;
    F[h_] += S_ * I * T[h_] + joule - leak;
    if (!J) return;
    J[slots_[0]] -= S_ * I + K_; // d(F_c)/dTc
    J[slots_[1]] += K_;          // d(F_c)/dTh
    J[slots_[2]] += K_;          // d(F_h)/dTc
    J[slots_[3]] += S_ * I - K_; // d(F_h)/dTh
  }

  void breakpoints(std::vector<double>& out) const override {
    out.insert(out.end(), I_.corners().begin(), I_.corners().end());
  }

  double power_in(double t, const double* T) const override {
    const double I = I_.at(t);
    return S_ * I * (T[h_] - T[c_]) + I * I * R_;
  }

  double flow(double t, const double* T) const override {
    const double I = I_.at(t);
    return S_ * I * T[c_] - 0.5 * I * I * R_ - K_ * (T[h_] - T[c_]);
  }

private:
  int c_, h_;
  double S_;
  thermnet::lang::Signal I_;
  double R_, K_;
  int slots_[4] = {};
};

thermnet::ElementPlugin make_peltier() {
  thermnet::lang::ElementSchema s;
  s.kind = "peltier";
  s.terminals = 2;
  s.doc = "thermoelectric cooler pumping heat from its first (cold) to its second (hot) terminal";
  s.is_source = false; // its hot side is usually a heat sink boundary
  s.keys.push_back(Key("S", seebeck, "Seebeck coefficient of the module [V/K]").required());
  s.keys.push_back(
      Key("I", current, "electric current [A], a constant or a signal").required().signal());
  s.keys.push_back(Key("R", ohm, "electrical resistance [V/A] (ohm)").required().positive());
  s.keys.push_back(
      Key("K", dim::conductance, "thermal conductance cold-hot [W/K]").required().positive());
  return thermnet::ElementPlugin{
      std::move(s), [](const thermnet::lang::ElementSpec& e) -> std::unique_ptr<Element> {
        return std::make_unique<Peltier>(e.nodes()[0], e.nodes()[1], e.number("S"),
                                         e.values.at("I"), e.number("R"), e.number("K"));
      }};
}

} // namespace

THERMNET_PLUGIN(registrar) {
  registrar.add_element(make_peltier());
}
