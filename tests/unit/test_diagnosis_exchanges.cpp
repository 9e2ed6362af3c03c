// Which candidates stand in for one another across a boundary: a link to an unmeasured node tied
// to a boundary against the link to that boundary (boundary_exchanges), a link to a boundary
// against the link to the nodes tied to it (tied_node_exchanges), and a link against the links
// from one of its ends to the other end's neighbours (neighbour_exchanges).

#include "kernel/diagnosis/selection.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

namespace thermnet::detail {
namespace {

/// A candidate entry of `kind` (and `mechanism`) on `nodes`.
Entry entry(std::string kind, std::vector<std::string> nodes, std::string mechanism = "") {
  Entry e;
  e.c.kind = std::move(kind);
  e.c.nodes = std::move(nodes);
  e.c.mechanism = std::move(mechanism);
  e.own = e.c;
  return e;
}

/// The node lists of entries[i] for each i in `idx`, "kind:mechanism:a,b".
std::vector<std::string> named(const std::vector<Entry>& entries,
                               const std::vector<std::size_t>& idx) {
  std::vector<std::string> out;
  for (std::size_t i : idx) {
    std::string s = entries[i].c.kind + ":" + entries[i].c.mechanism + ":";
    for (const auto& n : entries[i].c.nodes)
      s += n + (&n == &entries[i].c.nodes.back() ? "" : ",");
    out.push_back(s);
  }
  return out;
}

/// Evidence of one case of the model `text` whose measured nodes are `measured` (no data: the
/// exchanges read the network and which nodes are measured only).
Evidence evidence_of(const std::string& text, const std::vector<std::string>& measured) {
  test::TempDir dir("exchanges");
  test::LoadedModel m(dir.write("m.tnet", text), test::Lint::clean);
  Evidence ev;
  ev.cases.emplace_back();
  ev.cases.front().spec = m.model->instantiate();
  for (const auto& name : measured)
    ev.cases.front().rows.push_back(ev.cases.front().spec.node_index(name));
  return ev;
}

} // namespace

TEST_CASE("diagnosis exchanges: boundaries for unmeasured ends, tied nodes for boundaries") {
  // sink is a boundary; a (measured) and b (unmeasured) are bolted to it; c (measured) is free.
  const Evidence ev = evidence_of(R"(
boundary sink T = 20
node a C = 10
node b C = 10
node c C = 10
conductance ga a sink G = 5
conductance gb b sink G = 5
conductance gc a c G = 0.5
conductance gd b c G = 0.5
)",
                                  {"a", "c"});
  REQUIRE(ev.unobserved(ev.cases.front().spec.node_index("b")));

  const std::vector<Entry> entries = {entry("missing_link", {"c", "b"}, "linear"),
                                      entry("missing_link", {"sink", "c"}, "linear"),
                                      entry("missing_link", {"sink", "c"}, "radiation"),
                                      entry("missing_link", {"c", "a"}, "linear"),
                                      entry("missing_source", {"c"}),
                                      entry("missing_link", {"sink", "b"}, "linear")};

  SUBCASE("an unmeasured end is exchanged for the boundary it is tied to, either mechanism") {
    CHECK(named(entries, boundary_exchanges(entries, ev, entries[0].c)) ==
          std::vector<std::string>{"missing_link:linear:sink,c", "missing_link:radiation:sink,c"});
  }
  SUBCASE("a measured end is not exchanged") {
    CHECK(boundary_exchanges(entries, ev, entries[3].c).empty());
  }
  SUBCASE("a boundary is exchanged for the nodes tied to it, measured ones first") {
    // a (measured) before b (unmeasured); c is not tied to the sink.
    CHECK(named(entries, tied_node_exchanges(entries, ev, entries[2].c)) ==
          std::vector<std::string>{"missing_link:linear:c,a", "missing_link:linear:c,b"});
  }
  SUBCASE("a candidate naming no boundary has no tied-node exchange") {
    CHECK(tied_node_exchanges(entries, ev, entries[0].c).empty());
  }
}

TEST_CASE("diagnosis exchanges: a link's ends for their neighbours, same mechanism") {
  // A chain a - b - c - d, a tied to the boundary sink; b is not measured.
  const Evidence ev = evidence_of(R"(
boundary sink T = 20
node a C = 10
node b C = 10
node c C = 10
node d C = 10
conductance g0 a sink G = 5
conductance g1 a b G = 1
conductance g2 b c G = 1
conductance g3 c d G = 1
)",
                                  {"a", "c", "d"});
  REQUIRE(ev.unobserved(ev.cases.front().spec.node_index("b")));

  const std::vector<Entry> entries = {entry("missing_link", {"a", "c"}, "linear"),
                                      entry("missing_link", {"b", "c"}, "linear"),
                                      entry("missing_link", {"b", "c"}, "radiation"),
                                      entry("missing_link", {"a", "d"}, "linear"),
                                      entry("missing_link", {"a", "b"}, "linear"),
                                      entry("missing_link", {"sink", "c"}, "linear"),
                                      entry("missing_source", {"c"})};

  SUBCASE("each end for its neighbours that are nodes, measured ones first") {
    // a -> b (the sink is a boundary: tied_node_exchanges' business); c -> d (measured), then b.
    CHECK(named(entries, neighbour_exchanges(entries, ev, entries[0].c)) ==
          std::vector<std::string>{"missing_link:linear:b,c", "missing_link:linear:a,d",
                                   "missing_link:linear:a,b"});
  }
  SUBCASE("only links have neighbour exchanges") {
    CHECK(neighbour_exchanges(entries, ev, entries[6].c).empty());
  }
}

} // namespace thermnet::detail
