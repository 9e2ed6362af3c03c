// Element plugin 'convection': convection with a given coefficient, G = h A
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

ElementPlugin make_convection() {
  lang::ElementSchema s;
  s.kind = "convection";
  s.terminals = 2;
  s.doc = "convection with a given coefficient, G = h A";
  s.keys.push_back(Key("h", lang::dim::heat_transfer_coeff, "convection coefficient [W/(m^2*K)]")
                       .required()
                       .positive());
  s.keys.push_back(Key("A", lang::dim::area, "wetted area [m^2]").required().positive());
  s.conductance = [](const lang::KeyValues& v) { return v.at("h") * v.at("A"); };
  return linear_plugin(std::move(s));
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_convection);
} // namespace thermnet
