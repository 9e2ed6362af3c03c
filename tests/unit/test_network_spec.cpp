// Tests of the compact elaborated network: ElementSpec's accessors, its rare members behind one
// pointer (copied with it), KeySignals keyed by the schema's names, NodeSpec's description.
#include "kernel/core/element_registry.hpp"
#include "lang/network_spec.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

using thermnet::lang::Composite;
using thermnet::lang::ElementSpec;
using thermnet::lang::KeySchema;
using thermnet::lang::NodeSpec;
using thermnet::lang::Signal;

namespace {

const thermnet::lang::ElementSchema& schema_of(const char* kind) {
  const auto* s = thermnet::element_catalog().find(kind);
  REQUIRE(s != nullptr);
  return *s;
}

} // namespace

TEST_CASE("ElementSpec: the kind is the schema's, the terminals one or two, keys of the schema") {
  ElementSpec e;
  CHECK(e.kind().empty());
  CHECK(e.nodes().empty());
  e.schema = &schema_of("conductance");
  e.name = "g1";
  CHECK(e.kind() == "conductance");
  e.set_nodes(std::array{3, 7});
  REQUIRE(e.nodes().size() == 2);
  CHECK(e.nodes()[0] == 3);
  CHECK(e.nodes()[1] == 7);
  e.set_nodes(std::array{5});
  CHECK(e.nodes().size() == 1);
  CHECK_THROWS_AS(e.set_nodes(std::array{1, 2, 3}), std::invalid_argument);
  CHECK_THROWS_AS(e.set_nodes({}), std::invalid_argument);

  e.set("G", Signal::of(0.5));
  CHECK(e.number("G") == 0.5);
  e.set("G", Signal::of(2.0)); // replaces
  CHECK(e.values.size() == 1);
  CHECK(e.number("G") == 2.0);
  CHECK_THROWS_AS(e.set("R", Signal::of(1.0)), std::invalid_argument);
  // The key name is a view of the schema's own string, not a copy.
  CHECK(e.values.begin()->first.data() == e.schema->key("G")->name.data());
}

TEST_CASE("KeySignals: sorted by key, one inline and more on the heap, found by name") {
  const auto& radiation = schema_of("radiation");
  ElementSpec e;
  e.schema = &radiation;
  for (const char* k : {"eps2", "A", "F", "eps1"})
    e.set(k, Signal::of(static_cast<double>(std::string(k).size())));
  std::vector<std::string> keys;
  for (const auto& [k, s] : e.values)
    keys.emplace_back(k);
  CHECK(keys == std::vector<std::string>{"A", "F", "eps1", "eps2"});
  CHECK(e.number("eps1") == 4.0);
  CHECK_FALSE(e.has("GR"));
  CHECK_THROWS_AS(e.values.at("GR"), std::out_of_range);
  CHECK(e.key_values().at("F") == 1.0);
  // emplace keeps a present value.
  CHECK_FALSE(e.values.emplace(*radiation.key("A"), Signal::of(9.0)).second);
  CHECK(e.number("A") == 1.0);
}

TEST_CASE("ElementSpec: composites and node-valued keys live apart and are copied with it") {
  ElementSpec block;
  block.set_composite(Composite::series);
  block.set_nodes(std::array{0, 1});
  CHECK(block.kind() == "series");
  CHECK(block.parts().empty());
  ElementSpec part;
  part.schema = &schema_of("resistor");
  part.set_nodes(block.nodes());
  part.set("R", Signal::of(2.0));
  block.edit_parts().push_back(part);
  block.edit_parts().push_back(part);

  ElementSpec copy = block;
  copy.edit_parts()[0].set("R", Signal::of(4.0));
  CHECK(block.parts()[0].number("R") == 2.0); // the copy has its own parts
  CHECK(copy.parts()[0].number("R") == 4.0);
  CHECK(copy.parts().size() == 2);
  CHECK(std::ranges::equal(copy.parts()[1].nodes(), block.nodes()));
  block.set_composite(Composite::parallel);
  CHECK(block.kind() == "parallel");

  const auto& thermostat = schema_of("thermostat");
  ElementSpec t;
  t.schema = &thermostat;
  CHECK_FALSE(t.node_key("sense"));
  t.add_node_key(*thermostat.key("sense"), 4);
  const ElementSpec t2 = t;
  CHECK(t2.node_key("sense") == 4);
  CHECK_FALSE(t2.node_key("other"));
}

TEST_CASE("NodeSpec: a description only when written, copied with the node") {
  NodeSpec n;
  CHECK(n.doc().empty());
  n.set_doc("gas gap");
  const NodeSpec m = n;
  n.set_doc("");
  CHECK(n.doc().empty());
  CHECK(m.doc() == "gas gap");
}

TEST_CASE("Signal: constant without a shape; the kind lives with the corners") {
  Signal s = Signal::of(3.0);
  CHECK(s.kind() == Signal::Kind::constant);
  CHECK(s.shape_if() == nullptr);
  auto& corners = s.shape(Signal::Kind::step);
  corners.t = {0.0, 10.0};
  corners.v = {1.0, 2.0};
  const Signal c = s;
  CHECK(c.kind() == Signal::Kind::step);
  CHECK(c.at(5.0) == 1.0);
  CHECK(c.at(10.0) == 2.0);
}
