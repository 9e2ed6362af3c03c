// Element plugin 'conduction': plane conduction, G = k A / L
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

ElementPlugin make_conduction() {
  lang::ElementSchema s;
  s.kind = "conduction";
  s.terminals = 2;
  s.doc = "plane conduction, G = k A / L";
  s.keys.push_back(
      Key("k", lang::dim::conductivity, "thermal conductivity [W/(m*K)]").required().positive());
  s.keys.push_back(Key("L", lang::dim::length, "conduction length [m]").required().positive());
  s.keys.push_back(Key("A", lang::dim::area, "cross-section area [m^2]").required().positive());
  s.conductance = [](const lang::KeyValues& v) { return v.at("k") * v.at("A") / v.at("L"); };
  return linear_plugin(std::move(s));
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_conduction);
} // namespace thermnet
