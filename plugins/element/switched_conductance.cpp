// Element plugin 'switched_conductance': a linear link that conducts only while a schedule is on,
// Q = G on(t) (T_a - T_b) -- a door or a lid opened at known times.
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

/// A conductance G scaled by a schedule on(t) in [0, 1].
class SwitchedLink final : public Element {
public:
  SwitchedLink(int a, int b, double G, lang::Signal on) : a_(a), b_(b), G_(G), on_(std::move(on)) {}
  void declare(JacobianLayout& layout) override { declare_link(layout, a_, b_, slots_); }
  void stamp(double t, const double* T, double* F, double* J) const override {
    const double g = G_ * on_.at(t);
    stamp_link(F, J, a_, b_, g * (T[a_] - T[b_]), g, -g, slots_);
  }
  /// Under a step schedule (or a constant) the link is linear with G on fixed between corners.
  bool jacobian_piecewise_constant() const override {
    return on_.kind() == lang::Signal::Kind::constant || on_.kind() == lang::Signal::Kind::step;
  }
  void breakpoints(std::vector<double>& out) const override {
    out.insert(out.end(), on_.corners().begin(), on_.corners().end());
  }
  double flow(double t, const double* T) const override { return G_ * on_.at(t) * (T[a_] - T[b_]); }
  /// dQ = (dG on + G d on) (T_a - T_b).
  bool key_derivative(double t, const double* T, const lang::KeySignals& rates,
                      double* dF) const override {
    double dg = 0.0;
    for (const auto& [key, rate] : rates) {
      if (key == "G")
        dg += rate.at(t) * on_.at(t);
      else if (key == "on")
        dg += G_ * rate.at(t);
      else
        return false;
    }
    const double dq = dg * (T[a_] - T[b_]);
    dF[a_] -= dq;
    dF[b_] += dq;
    return true;
  }

private:
  int a_, b_;
  double G_;
  lang::Signal on_;
  int slots_[4] = {0, 0, 0, 0};
};

ElementPlugin make_switched_conductance() {
  lang::ElementSchema s;
  s.kind = "switched_conductance";
  s.terminals = 2;
  s.doc = "linear link switched by a schedule, Q = G on(t) (T_a - T_b)";
  s.keys.push_back(
      Key("G", lang::dim::conductance, "conductance while on [W/K]").required().positive());
  Key on = Key("on", lang::dim::none, "schedule in [0, 1]: 1 on, 0 off, a constant or a signal")
               .required()
               .non_negative()
               .signal();
  on.k.max = 1.0;
  s.keys.push_back(on);
  return ElementPlugin{std::move(s), [](const lang::ElementSpec& e) -> std::unique_ptr<Element> {
                         return std::make_unique<SwitchedLink>(e.nodes()[0], e.nodes()[1],
                                                               e.number("G"), e.values.at("on"));
                       }};
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_switched_conductance);
} // namespace thermnet
