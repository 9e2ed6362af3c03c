/// Unit tests of `require`: the syntax tree of each form, its elaboration into SI limits and
/// resolved members, and RequirementCheck on rows whose answers are known.

#include "kernel/core/element_registry.hpp"
#include "kernel/core/requirement_check.hpp"
#include "lang/model.hpp"
#include "lang/parser.hpp"

#include <doctest/doctest.h>

#include <memory>
#include <string>
#include <vector>

using namespace thermnet;
using namespace thermnet::lang;

namespace {

const char* const base = R"(boundary air T = -10
node lens1 C = 100
node lens2 C = 100
node zone1 C = 50
conductance g1 lens1 air G = 1
conductance g2 lens2 lens1 G = 2
conductance g3 zone1 lens1 G = 2
thermostat h1 lens1 P = 20 on = 17 off = 20
heater h2 lens2 P = 4
)";

struct Loaded {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  std::unique_ptr<Model> model;
  explicit Loaded(const std::string& extra) {
    model =
        Model::from_text("m.tnet", std::string(base) + extra, element_catalog(), sources, diags);
    model->lint(diags);
  }
};

} // namespace

TEST_CASE("require: the syntax tree of a band with from, cases and description") {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  const FileId id = sources.add(
      "t.tnet",
      "require band \"lens*\" \"zone*\" 15 .. 25 [degC] from 2750 [s] in a, b \"optics\"\n");
  ast::File f = parse_file(id, sources, diags);
  REQUIRE(diags.error_count() == 0);
  REQUIRE(f.statements.size() == 1);
  const auto& r = *std::get<ast::Boxed<ast::RequireStmt>>(f.statements[0]);
  CHECK(r.kind.name == "band");
  REQUIRE(r.groups.size() == 2);
  CHECK(r.groups[1].text == "zone*");
  CHECK(r.lo.has_value());
  CHECK(r.bound.name.empty());
  CHECK(r.from.has_value());
  REQUIRE(r.cases.size() == 2);
  CHECK(r.cases[1].name == "b");
  REQUIRE(r.doc);
  CHECK(r.doc->text == "optics");
}

TEST_CASE("require: an element kind called require still parses as an element") {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  const FileId id = sources.add("t.tnet", "require r1 a b G = 1\n");
  ast::File f = parse_file(id, sources, diags);
  CHECK(diags.error_count() == 0);
  REQUIRE(f.statements.size() == 1);
  CHECK(std::holds_alternative<ast::ElementStmt>(f.statements[0]));
}

TEST_CASE("require: a malformed limit is a syntax error at its place") {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  const FileId id = sources.add("t.tnet", "node a C = 1\nrequire energy \"h1\" max\n");
  parse_file(id, sources, diags);
  REQUIRE(diags.error_count() == 1);
  const auto& d = diags.all().front();
  CHECK(d.code == "syntax");
  const LineCol lc = sources.line_col(id, d.at->begin);
  CHECK(lc.line == 2);
  CHECK(lc.column == 24);
}

TEST_CASE("require: limits in SI, units of reports as written, members resolved") {
  Loaded m("require band \"lens*\" 15 .. 25 [degC] from 1 [min]\n"
           "require band \"zone1\" 288 .. 298 [K]\n"
           "require gradient \"lens1\" \"zone1\" max 5 [degC]\n"
           "require energy \"h*\" max 2 [kJ]\n"
           "require margin \"h1\" min 50 [%]\n"
           "case c { duration = 10 }\n");
  INFO(render_text(m.diags));
  REQUIRE(m.diags.error_count() == 0);
  const auto net = m.model->network("c");
  REQUIRE(net->requirements.size() == 5);
  const auto& band = net->requirements[0];
  CHECK(band.lo == doctest::Approx(288.15));
  CHECK(band.hi == doctest::Approx(298.15));
  CHECK(band.from == doctest::Approx(60));
  CHECK(band.members.size() == 2);
  CHECK(band.unit.text == "degC");
  CHECK(band.unit.shown(band.lo) == doctest::Approx(15));
  CHECK(net->requirements[1].lo == doctest::Approx(288)); // a bare LO takes HI's unit
  CHECK(net->requirements[2].hi == doctest::Approx(5));   // a difference: 5 degC is 5 K
  CHECK(net->requirements[2].others.size() == 1);
  CHECK(net->requirements[3].hi == doctest::Approx(2000));
  CHECK(net->requirements[3].members.size() == 2);
  CHECK(net->requirements[4].lo == doctest::Approx(0.5));
}

TEST_CASE("require: `in CASE` applies to that case only, whether or not the case sets a param") {
  // `a` sets no param (its network is the base model's, taken over), `b` sets one (elaborated).
  Loaded m("param P = 4 [W]\n"
           "require band \"lens*\" 15 .. 25 [degC] in a\n"
           "require power \"h*\" max 30 [W] in b\n"
           "require gradient \"lens*\" max 5 [K]\n"
           "case a { duration = 10 ; h2.P = 3 }\n"
           "case b { duration = 10 ; P = 5 }\n");
  INFO(render_text(m.diags));
  REQUIRE(m.diags.error_count() == 0);
  const auto kinds = [&](const std::string& c) {
    std::vector<RequirementKind> out;
    for (const auto& r : m.model->network(c)->requirements)
      out.push_back(r.kind);
    return out;
  };
  CHECK(kinds("a") == std::vector{RequirementKind::band, RequirementKind::gradient});
  CHECK(kinds("b") == std::vector{RequirementKind::power, RequirementKind::gradient});
}

TEST_CASE("require: unknown names, wrong forms and units are errors at the statement") {
  Loaded m("require band \"lense*\" 15 .. 25\n"
           "require power \"g1\" max 3 [W]\n"
           "require band \"lens*\" max 25\n"
           "require power \"h*\" max 30 [K]\n"
           "require margin \"h2\" min 50 [%] in nowhere\n"
           "case c { duration = 10 }\n");
  std::vector<std::string> codes;
  std::vector<unsigned> lines;
  for (const auto& d : m.diags.all()) {
    codes.push_back(d.code);
    lines.push_back(m.sources.line_col(d.at->file, d.at->begin).line);
  }
  CHECK(codes == std::vector<std::string>{"unknown-node", "unknown-element", "bad-requirement",
                                          "unit-mismatch", "bad-requirement"});
  CHECK(lines == std::vector<unsigned>{10, 11, 12, 13, 14});
}

TEST_CASE("RequirementCheck: band, gradient, power, energy and margin on known rows") {
  Loaded m("require band \"lens*\" 15 .. 25 from 1\n"
           "require gradient \"lens*\" max 2\n"
           "require power \"h*\" max 22 [W]\n"
           "require energy \"h1\" max 30 [J]\n"
           "require margin \"h1\" min 50 [%]\n"
           "case c { duration = 10 }\n");
  REQUIRE(m.diags.error_count() == 0);
  const auto net = m.model->network("c");
  RequirementCheck check(*net);
  CHECK(check.needs_heat());
  // nodes: air, lens1, lens2, zone1; elements g1, g2, g3, h1, h2
  const auto K = [](double c) { return c + 273.15; };
  std::vector<std::vector<double>> heat(5, std::vector<double>(2, 0.0));
  heat[4][0] = 4.0;
  heat[3][0] = 20.0;
  check.add(0.0, {K(-10), K(10), K(20), K(18)}, heat); // before `from`: the band ignores it
  heat[3][0] = 0.0;
  check.add(2.0, {K(-10), K(16), K(19), K(18)}, heat);
  check.add(4.0, {K(-10), K(17), K(18), K(18)}, heat);
  const auto o = check.outcomes();
  REQUIRE(o.size() == 5);
  CHECK(o[0].met);
  CHECK(o[0].slack == doctest::Approx(1.0)); // lens1 at 16 degC, 1 K above 15
  CHECK(o[0].where == "lens1");
  CHECK(!o[1].met); // lens spread 10 K at t = 0
  CHECK(o[1].slack == doctest::Approx(-8.0));
  CHECK(o[1].time == 0.0);
  CHECK(o[1].where == "lens2 - lens1");
  CHECK(!o[2].met); // 24 W at t = 0
  CHECK(o[2].slack == doctest::Approx(-2.0));
  CHECK(o[3].met); // trapezoid: (20 + 0) / 2 * 2 s = 20 J
  CHECK(o[3].worst == doctest::Approx(20.0));
  CHECK(o[4].met); // mean 5 W of 20 W installed: margin 300 %
  CHECK(o[4].worst == doctest::Approx(3.0));
  CHECK(o[4].duty == doctest::Approx(0.25));
}
