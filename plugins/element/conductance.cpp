// Element plugin 'conductance': linear link, Q = G (T_a - T_b)
#include "kernel/core/element_registry.hpp"

namespace thermnet {
namespace {

ElementPlugin make_conductance() {
  lang::ElementSchema s;
  s.kind = "conductance";
  s.terminals = 2;
  s.doc = "linear link, Q = G (T_a - T_b)";
  s.keys.push_back(Key("G", lang::dim::conductance, "conductance [W/K]").required().positive());
  s.conductance = [](const lang::KeyValues& v) { return v.at("G"); };
  return linear_plugin(std::move(s));
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_conductance);
} // namespace thermnet
