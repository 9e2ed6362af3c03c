// Element plugin 'cylinder_conduction': radial conduction through a cylindrical shell.
#include "kernel/core/element_registry.hpp"

#include <cmath>
#include <numbers>

namespace thermnet {
namespace {

ElementPlugin make_cylinder_conduction() {
  lang::ElementSchema s;
  s.kind = "cylinder_conduction";
  s.terminals = 2;
  s.doc = "radial conduction through a cylindrical shell, G = 2 pi k L / ln(r_out/r_in)";
  s.keys.push_back(
      Key("k", lang::dim::conductivity, "thermal conductivity [W/(m*K)]").required().positive());
  s.keys.push_back(Key("r_in", lang::dim::length, "inner radius [m]").required().positive());
  s.keys.push_back(Key("r_out", lang::dim::length, "outer radius [m]").required().positive());
  s.keys.push_back(Key("L", lang::dim::length, "cylinder length [m]").required().positive());
  s.check = [](const lang::KeyValues& v) {
    std::vector<lang::KeyProblem> p;
    if (!(v.at("r_out") > v.at("r_in"))) p.push_back({"r_out", "r_out must be larger than r_in"});
    return p;
  };
  s.conductance = [](const lang::KeyValues& v) {
    return 2.0 * std::numbers::pi * v.at("k") * v.at("L") / std::log(v.at("r_out") / v.at("r_in"));
  };
  return linear_plugin(std::move(s));
}

} // namespace
THERMNET_REGISTER(ElementPlugin, make_cylinder_conduction);
} // namespace thermnet
