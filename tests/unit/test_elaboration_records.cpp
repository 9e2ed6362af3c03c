// Elaborating a case again from a recorded elaboration (Model::instantiate_near) gives the network
// a full elaboration gives, for every ranged param of every bundled model moved alone and all
// together, and for the ways a param reaches a value: through consts, a submodel's param and const,
// a loop, a series block, a signal's expression, a case's setting of a fixed param.

#include "loaded_model.hpp"
#include "temp_dir.hpp"

#include "lang/elaborator.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

using namespace thermnet;

namespace {

bool same_signal(const lang::Signal& a, const lang::Signal& b) {
  if (a.kind() != b.kind()) return false;
  switch (a.kind()) {
  case lang::Signal::Kind::constant:
    return a.constant == b.constant;
  case lang::Signal::Kind::step:
  case lang::Signal::Kind::pwl:
    return a.times() == b.times() && a.values() == b.values();
  case lang::Signal::Kind::expression: {
    // (two elaborations compile two programs: compared by their values, at their corners and
    // over a day)
    if (a.times() != b.times()) return false;
    std::vector<double> ts = a.times();
    for (int k = 0; k <= 200; ++k)
      ts.push_back(432.0 * k);
    return std::all_of(ts.begin(), ts.end(), [&](double t) { return a.at(t) == b.at(t); });
  }
  }
  return false;
}

bool same_element(const lang::ElementSpec& a, const lang::ElementSpec& b) {
  if (a.name != b.name || a.kind() != b.kind() || a.schema != b.schema) return false;
  const auto na = a.nodes(), nb = b.nodes();
  if (!std::equal(na.begin(), na.end(), nb.begin(), nb.end())) return false;
  if (a.values.size() != b.values.size()) return false;
  for (auto ia = a.values.begin(), ib = b.values.begin(); ia != a.values.end(); ++ia, ++ib)
    if (ia->first != ib->first || !same_signal(ia->second, ib->second)) return false;
  const auto pa = a.parts(), pb = b.parts();
  if (pa.size() != pb.size()) return false;
  for (std::size_t k = 0; k < pa.size(); ++k)
    if (!same_element(pa[k], pb[k])) return false;
  return true;
}

/// Every node, element and case setting a simulation reads, compared exactly.
void require_same(const lang::NetworkSpec& a, const lang::NetworkSpec& b) {
  REQUIRE(a.nodes.size() == b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    INFO("node " << a.nodes[i].name);
    CHECK(a.nodes[i].name == b.nodes[i].name);
    CHECK(a.nodes[i].boundary == b.nodes[i].boundary);
    CHECK(a.nodes[i].C == b.nodes[i].C);
    CHECK(a.nodes[i].T0 == b.nodes[i].T0);
    CHECK(same_signal(a.nodes[i].T, b.nodes[i].T));
  }
  REQUIRE(a.elements.size() == b.elements.size());
  for (std::size_t k = 0; k < a.elements.size(); ++k) {
    INFO("element " << a.elements[k].name);
    CHECK(same_element(a.elements[k], b.elements[k]));
  }
  CHECK(a.settings.name == b.settings.name);
  CHECK(a.settings.duration == b.settings.duration);
  CHECK(a.settings.initial == b.settings.initial);
  CHECK(a.settings.output_times == b.settings.output_times);
  CHECK(a.requirements.size() == b.requirements.size());
}

bool differ(const lang::NetworkSpec& a, const lang::NetworkSpec& b) {
  for (std::size_t i = 0; i < a.nodes.size(); ++i)
    if (a.nodes[i].C != b.nodes[i].C || a.nodes[i].T0 != b.nodes[i].T0 ||
        !same_signal(a.nodes[i].T, b.nodes[i].T))
      return true;
  for (std::size_t k = 0; k < a.elements.size(); ++k)
    if (!same_element(a.elements[k], b.elements[k])) return true;
  return false;
}

/// Checks every case of `model`: each ranged param moved alone, then all of them, elaborated from
/// the declared values' record and from a moved record back to the declared values; returns how
/// many moved networks differed from the declared one.
int check_model(const lang::Model& model) {
  std::vector<lang::ParamInfo> ranged;
  for (const auto& p : model.params())
    if (p.lo && p.hi) ranged.push_back(p);
  int moved_networks = 0;
  for (const std::string& c : model.run_case_names()) {
    INFO("case " << c);
    std::shared_ptr<const lang::ElaborationRecord> declared;
    const lang::NetworkSpec base = model.instantiate_recorded(c, {}, declared);
    require_same(base, model.instantiate(c));
    if (!declared) continue;
    lang::ParamValues all;
    for (const auto& p : ranged) {
      INFO("param " << p.name);
      const lang::ParamValues one{{p.name, p.value + 0.37 * (*p.hi - p.value)}};
      all.insert(*one.begin());
      const lang::NetworkSpec full = model.instantiate(c, one);
      std::shared_ptr<const lang::ElaborationRecord> moved;
      require_same(model.instantiate_near(*declared, one, &moved), full);
      moved_networks += differ(full, base) ? 1 : 0;
      REQUIRE(moved);
      require_same(model.instantiate_near(*moved, {}), base); // back: the param moved by absence
    }
    const lang::NetworkSpec full = model.instantiate(c, all);
    std::shared_ptr<const lang::ElaborationRecord> at_all;
    require_same(model.instantiate_near(*declared, all, &at_all), full);
    REQUIRE(at_all);
    require_same(model.instantiate_near(*at_all, {}), base);
  }
  return moved_networks;
}

} // namespace

TEST_CASE("elaborations from a record equal full ones on every bundled model") {
  const std::string models = std::string(THERMNET_TEST_DIR) + "/../models/";
  int moved = 0;
  for (const char* path :
       {"aerial_camera/camera.tnet", "aerial_camera/extended.tnet", "incubator/incubator.tnet",
        "incubator/incubator7.tnet", "examples/two_plates.tnet", "examples/thermostat_box.tnet",
        "examples/boxes.tnet", "examples/panel.tnet", "examples/series_slab.tnet",
        "heater_design/designed.tnet", "heater_design/leak.tnet", "heater_design/heaters.tnet",
        "armadillo/house.tnet", "armadillo/house_2r2c.tnet"}) {
    INFO(std::string(path));
    const test::LoadedModel m(models + path);
    moved += check_model(*m.model);
  }
  CHECK(moved > 20); // the params move networks: the comparisons are not of equal networks only
}

TEST_CASE("elaborations from a record follow params through every path to a value") {
  const test::TempDir dir("near");
  const std::string path = (dir.path / "paths.tnet").string();
  std::ofstream(path) << R"(model paths
param h = 8 [W/(m^2*K)] range 2 .. 20 "film coefficient"
param k = 0.2 [W/(m*K)] range 0.05 .. 1
param q = 3 [W] range 0 .. 10
param g = 0.5 [W/K] range 0.1 .. 2
param fixed = 2
const area = 0.01 [m^2]
const h_area = h * area
submodel box(mount) {
  param G = 1 [W/K]
  param C0 = 100 [J/K]
  const C_wall = 2 * C0
  node wall C = C_wall
  node core C = C0
  conductance leg wall mount G = G
}
boundary air T = 20
node a C = 50 [J/K]
node b C = 60 [J/K] * fixed
node p[1 .. 4] C = 10 [J/K]
for i in 1 .. 3 { conductance s[i] p[i] p[i + 1] G = g * i }
convection film a air h = h A = area
conductance hg a b G = h_area
series mount b air { contact h = 2500 A = 30e-4 ; conduction k = k L = 3 [mm] A = 54.8 [mm^2] }
box bx a G = g C0 = 40 [J/K] * (1 + q / 10 [W])
heater hot b P = q * (1 + 0.5 * sin(time / 600))
conductance tie p[1] a G = 0.3
case warm {
  duration = 1 [h]
  b.T0 = 30
  fixed = 1 + h / 10 [W/(m^2*K)]
}
)";
  const test::LoadedModel m(path, test::Lint::clean);
  CHECK(check_model(*m.model) == 4); // each of the four ranged params moves the network
}
