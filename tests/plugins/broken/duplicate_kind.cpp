// A plugin that registers a kind thermnet already has.
#include "kernel/plugin_host/plugin_api.hpp"

namespace {
thermnet::ElementPlugin make_conductance() {
  thermnet::lang::ElementSchema s;
  s.kind = "conductance";
  s.doc = "a second conductance";
  s.keys.push_back(thermnet::Key("G", thermnet::lang::dim::conductance, "conductance [W/K]"));
  s.conductance = [](const thermnet::lang::KeyValues& v) { return v.at("G"); };
  return thermnet::linear_plugin(std::move(s));
}
} // namespace

THERMNET_PLUGIN(registrar) {
  registrar.add_element(make_conductance());
}
