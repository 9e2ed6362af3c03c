// Element plugin 'resistor': linear link given by its thermal resistance, G = 1/R
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

ElementPlugin make_resistor() {
  lang::ElementSchema s;
  s.kind = "resistor";
  s.terminals = 2;
  s.doc = "linear link given by its thermal resistance, G = 1/R";
  s.keys.push_back(
      Key("R", lang::dim::resistance, "thermal resistance [K/W]").required().positive());
  s.conductance = [](const lang::KeyValues& v) { return 1.0 / v.at("R"); };
  return linear_plugin(std::move(s));
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_resistor);
} // namespace thermnet
