// Element plugin 'heater': a prescribed heat input P(t) into a node.
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

/// Adds P(t) to one node.
class Heater final : public Element {
public:
  Heater(int node, lang::Signal P) : node_(node), P_(std::move(P)) {}
  void declare(JacobianLayout&) override {}
  void stamp(double t, const double*, double* F, double*) const override { F[node_] += P_.at(t); }
  bool affine() const override { return true; }
  bool piecewise_linear_inputs() const override { return P_.piecewise_linear(); }
  void breakpoints(std::vector<double>& out) const override {
    out.insert(out.end(), P_.corners().begin(), P_.corners().end());
  }
  double power_in(double t, const double*) const override { return P_.at(t); }
  /// dF = dP/dp at t.
  bool key_derivative(double t, const double*, const lang::KeySignals& rates,
                      double* dF) const override {
    if (rates.size() != 1 || rates.begin()->first != "P") return false;
    dF[node_] += rates.begin()->second.at(t);
    return true;
  }

private:
  int node_;
  lang::Signal P_;
};

ElementPlugin make_heater() {
  lang::ElementSchema s;
  s.kind = "heater";
  s.terminals = 1;
  s.doc = "prescribed heat input into a node (negative for a sink)";
  s.is_source = true;
  s.keys.push_back(
      Key("P", lang::dim::power, "power [W], a constant or a signal").required().signal());
  return ElementPlugin{std::move(s), [](const lang::ElementSpec& e) -> std::unique_ptr<Element> {
                         return std::make_unique<Heater>(e.nodes()[0], e.values.at("P"));
                       }};
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_heater);
} // namespace thermnet
