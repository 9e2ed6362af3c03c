// Element plugin 'contact': contact conductance, G = h A
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

ElementPlugin make_contact() {
  lang::ElementSchema s;
  s.kind = "contact";
  s.terminals = 2;
  s.doc = "contact conductance, G = h A";
  s.keys.push_back(
      Key("h", lang::dim::heat_transfer_coeff, "contact heat transfer coefficient [W/(m^2*K)]")
          .required()
          .positive());
  s.keys.push_back(Key("A", lang::dim::area, "contact area [m^2]").required().positive());
  s.conductance = [](const lang::KeyValues& v) { return v.at("h") * v.at("A"); };
  return linear_plugin(std::move(s));
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_contact);
} // namespace thermnet
