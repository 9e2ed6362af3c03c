/// Unit tests of the parser: the AST of every statement form of the spec (positions included),
/// expression precedence and associativity, units through expressions, lexical rules, and the
/// location and recovery of syntax errors.

#include "lang/ast.hpp"
#include "lang/diagnostics.hpp"
#include "lang/evaluator.hpp"
#include "lang/parser.hpp"
#include "lang/source.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "spec_example.hpp"

using namespace thermnet::lang;

namespace {

/// One parsed file with its sources and diagnostics (not movable: the engine points at sources).
struct Parsed {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  ast::File file;
  FileId id = 0;

  explicit Parsed(const std::string& text) {
    id = sources.add("t.tnet", text);
    file = parse_file(id, sources, diags);
  }
  Parsed(const Parsed&) = delete;

  /// The text a tagged node was parsed from.
  std::string text_of(const ast::Tagged& t) const {
    return sources.text(id).substr(t.begin, t.end - t.begin);
  }
  /// "line:col" of a byte offset.
  std::string where(std::uint32_t offset) const {
    LineCol lc = sources.line_col(id, offset);
    return std::to_string(lc.line) + ":" + std::to_string(lc.column);
  }
  /// Codes of all diagnostics, in order.
  std::vector<std::string> codes() const {
    std::vector<std::string> out;
    for (const auto& d : diags.all())
      out.push_back(d.code);
    return out;
  }
  /// "line:col" where the first diagnostic is reported.
  std::string first_at() const {
    REQUIRE(!diags.all().empty());
    REQUIRE(diags.all().front().at.has_value());
    return where(diags.all().front().at->begin);
  }
  /// The text under the first diagnostic's caret.
  std::string first_mark() const {
    const Diagnostic& d = diags.all().front();
    Span m = d.mark ? *d.mark : *d.at;
    return sources.text(id).substr(m.begin, m.end - m.begin);
  }
  /// The statement at an index, as a given alternative.
  template <typename T> const T& stmt(std::size_t i) const {
    REQUIRE(i < file.statements.size());
    const T* s = std::get_if<T>(&file.statements[i]);
    REQUIRE(s != nullptr);
    return *s;
  }
  /// The step/pwl signal a value consists of, or nullptr.
  const ast::PointSignal* point_signal(const ast::Value& v) const {
    const ast::SignalExpr* se = signal(v);
    return se ? std::get_if<ast::PointSignal>(se) : nullptr;
  }
  /// The table a value consists of, or nullptr.
  const ast::TableSignal* table(const ast::Value& v) const {
    const ast::SignalExpr* se = signal(v);
    return se ? std::get_if<ast::TableSignal>(se) : nullptr;
  }
  /// The signal a value consists of, or nullptr.
  const ast::SignalExpr* signal(const ast::Value& v) const {
    const ast::Expr* e = v.as_expr();
    if (!e || !e->valid() || file.node(e->root).op != ast::ExprNode::Op::signal) return nullptr;
    return &file.signals[file.node(e->root).a];
  }
};

auto parse(const std::string& text) {
  return std::make_unique<Parsed>(text);
}

/// Parses `const x = EXPR` and evaluates EXPR (no names but pi and sigma).
Quantity eval(const std::string& expr) {
  auto p = parse("const x = " + expr + "\n");
  INFO("expression: ", expr);
  for (const auto& d : p->diags.all())
    INFO(d.message);
  REQUIRE(p->diags.all().empty());
  const auto& c = p->stmt<ast::ConstStmt>(0);
  Evaluator ev(p->file, [](const ast::Identifier& id, FileId) -> Quantity {
    throw EvalError(
        DiagnosticEngine::make(DiagId::unknown_name, std::nullopt, std::nullopt, id.name));
  });
  return ev.eval(c.value);
}

double value(const std::string& expr) {
  return eval(expr).value;
}

/// The code of the EvalError an expression raises, or "" if none.
std::string eval_error(const std::string& expr) {
  try {
    eval(expr);
  } catch (const EvalError& e) {
    return e.diag.code;
  }
  return "";
}

const ast::Expr& expr_of(const ast::Value& v) {
  const ast::Expr* e = v.as_expr();
  REQUIRE(e != nullptr);
  return *e;
}

} // namespace

// -----------------------------------------------------------------------------------------
// Statements

TEST_CASE("parser: model, include and plugin statements") {
  auto p = parse("model two_plates\ninclude \"parts/other.tnet\"\nplugin \"lib.so\"\n");
  CHECK(p->diags.all().empty());
  REQUIRE(p->file.statements.size() == 3);
  const auto& m = p->stmt<ast::ModelStmt>(0);
  CHECK(m.name.name == "two_plates");
  CHECK(p->text_of(m) == "model two_plates");
  CHECK(p->text_of(m.name) == "two_plates");
  const auto& inc = p->stmt<ast::IncludeStmt>(1);
  CHECK(inc.path.text == "parts/other.tnet");
  CHECK(p->text_of(inc.path) == "\"parts/other.tnet\"");
  CHECK(p->where(inc.begin) == "2:1");
  CHECK(p->stmt<ast::PluginStmt>(2).path.text == "lib.so");
}

TEST_CASE("parser: const and param with range and description") {
  auto p = parse("const k = 0.25\nparam h_gap = 4 [W/(m^2*K)] range 1 .. 10 \"gas gap\"\n"
                 "param fixed = 2\nparam d = 1 \"only a description\"\n");
  CHECK(p->diags.all().empty());
  const auto& c = p->stmt<ast::ConstStmt>(0);
  CHECK(c.name.name == "k");
  CHECK(p->text_of(c.value) == "0.25");
  const auto& h = p->stmt<ast::ParamStmt>(1);
  CHECK(h.name.name == "h_gap");
  CHECK(p->text_of(h.name) == "h_gap");
  CHECK(p->text_of(h.value) == "4 [W/(m^2*K)]");
  REQUIRE(h.range.has_value());
  CHECK(p->text_of(h.range->lo) == "1");
  CHECK(p->text_of(h.range->hi) == "10");
  CHECK(p->text_of(*h.range) == "1 .. 10");
  REQUIRE(h.doc != nullptr);
  CHECK(h.doc->text == "gas gap");
  CHECK(p->where(h.begin) == "2:1");
  CHECK(p->text_of(h) == "param h_gap = 4 [W/(m^2*K)] range 1 .. 10 \"gas gap\"");
  const auto& f = p->stmt<ast::ParamStmt>(2);
  CHECK_FALSE(f.range.has_value());
  CHECK(f.doc == nullptr);
  const auto& d = p->stmt<ast::ParamStmt>(3);
  CHECK_FALSE(d.range.has_value());
  REQUIRE(d.doc != nullptr);
  CHECK(d.doc->text == "only a description");
}

TEST_CASE("parser: a range written without spaces") {
  auto p = parse("param h = 4 range 1..10\nparam g = 1.5 range .5..2.5\n");
  CHECK(p->diags.all().empty());
  const auto& h = p->stmt<ast::ParamStmt>(0);
  REQUIRE(h.range.has_value());
  CHECK(p->text_of(h.range->lo) == "1");
  CHECK(p->text_of(h.range->hi) == "10");
  const auto& g = p->stmt<ast::ParamStmt>(1);
  CHECK(p->text_of(g.range->lo) == ".5");
  CHECK(p->text_of(g.range->hi) == "2.5");
}

TEST_CASE("parser: node and boundary statements") {
  auto p = parse("node plate2 C = 300 [J/K] T0 = 20 \"the plate\"\n"
                 "boundary ambient T = pwl(0: 20, 2750: -35)\nnode arith C = 0\n");
  CHECK(p->diags.all().empty());
  const auto& n = p->stmt<ast::NodeStmt>(0);
  CHECK(n.name.id.name == "plate2");
  REQUIRE(n.keys.size() == 2);
  CHECK(n.keys[0].key.name == "C");
  CHECK(p->text_of(n.keys[0]) == "C = 300 [J/K]");
  CHECK(p->text_of(expr_of(n.keys[0].value)) == "300 [J/K]");
  CHECK(n.keys[1].key.name == "T0");
  REQUIRE(n.doc != nullptr);
  CHECK(n.doc->text == "the plate");
  const auto& b = p->stmt<ast::NodeStmt>(1);
  CHECK(b.boundary);
  CHECK(b.name.id.name == "ambient");
  REQUIRE(b.keys.size() == 1);
  const auto* sig = p->point_signal(b.keys[0].value);
  REQUIRE(sig != nullptr);
  CHECK(sig->kind.name == "pwl");
  REQUIRE(sig->points.size() == 2);
  CHECK(p->text_of(sig->points[1].time) == "2750");
  CHECK(p->text_of(sig->points[1].value) == "-35");
  CHECK(p->text_of(*sig) == "pwl(0: 20, 2750: -35)");
  CHECK(p->where(p->stmt<ast::NodeStmt>(2).begin) == "3:1");
}

TEST_CASE("parser: two-terminal and one-terminal elements") {
  auto p = parse("convection gap plate1 plate2 h = h_gap A = 0.02\n"
                 "heater film plate1 P = step(0: 10, 2500: 0) \"the film\"\n"
                 "thermostat t n P = 5 on = 18 off = 22 sense = m\n");
  CHECK(p->diags.all().empty());
  const auto& e = p->stmt<ast::ElementStmt>(0);
  CHECK(e.kind.name == "convection");
  CHECK(e.name.id.name == "gap");
  REQUIRE(e.nodes.size() == 2);
  CHECK(e.nodes[0].id.name == "plate1");
  CHECK(e.nodes[1].id.name == "plate2");
  CHECK(p->text_of(e.nodes[1]) == "plate2");
  REQUIRE(e.keys.size() == 2);
  CHECK(e.keys[0].key.name == "h");
  CHECK(e.keys[1].key.name == "A");
  const auto& h = p->stmt<ast::ElementStmt>(1);
  CHECK(h.kind.name == "heater");
  REQUIRE(h.nodes.size() == 1);
  CHECK(h.nodes[0].id.name == "plate1");
  REQUIRE(h.keys.size() == 1);
  const auto* sig = p->point_signal(h.keys[0].value);
  REQUIRE(sig != nullptr);
  CHECK(sig->kind.name == "step");
  CHECK(sig->points.size() == 2);
  REQUIRE(h.doc != nullptr);
  CHECK(h.doc->text == "the film");
  const auto& t = p->stmt<ast::ElementStmt>(2);
  REQUIRE(t.keys.size() == 4);
  CHECK(t.keys[3].key.name == "sense");
}

TEST_CASE("parser: statement lists are viewed in place, also after the file is moved") {
  // Enough keys and terminals for several blocks of the file's list storage, lists of varying
  // length (a list that does not fit the rest of a block starts the next one).
  std::string text;
  const int count = 3000;
  for (int i = 0; i < count; ++i) {
    text += "conductance g" + std::to_string(i) + " a" + std::to_string(i);
    if (i % 2) text += " b" + std::to_string(i);
    for (int k = 0; k <= i % 4; ++k)
      text += " k" + std::to_string(k) + " = " + std::to_string(i * 10 + k);
    text += "\n";
  }
  text += "node n C = 10 T0 = max(1, 2, 3)\n";
  auto p = parse(text);
  CHECK(p->diags.all().empty());
  const auto& first = p->stmt<ast::ElementStmt>(0);
  const ast::KeyValue* first_keys = first.keys.data();
  const ast::File moved = std::move(p->file);
  REQUIRE(moved.statements.size() == count + 1);
  CHECK(std::get<ast::ElementStmt>(moved.statements[0]).keys.data() == first_keys);
  for (int i = 0; i < count; ++i) {
    const auto& e = std::get<ast::ElementStmt>(moved.statements[static_cast<std::size_t>(i)]);
    REQUIRE(e.nodes.size() == static_cast<std::size_t>(1 + i % 2));
    const std::string number = std::to_string(i);
    CHECK(e.nodes[0].id.name == std::string("a").append(number));
    if (i % 2) CHECK(e.nodes[1].id.name == std::string("b").append(number));
    REQUIRE(e.keys.size() == static_cast<std::size_t>(1 + i % 4));
    const ast::KeyValue& last = e.keys.back();
    CHECK(last.key.name == std::string("k").append(std::to_string(i % 4)));
    CHECK(moved.node(last.value.as_expr()->root).value == i * 10 + i % 4);
  }
  const auto& n = std::get<ast::NodeStmt>(moved.statements.back());
  REQUIRE(n.keys.size() == 2);
  const ast::ExprNode& call = moved.node(n.keys[1].value.as_expr()->root);
  REQUIRE(call.op == ast::ExprNode::Op::call);
  const auto args = moved.call_args(call);
  REQUIRE(args.size() == 3);
  CHECK(moved.node(args[2]).value == 3);
}

TEST_CASE("parser: table signal") {
  auto p = parse("heater h n P = table(\"power.csv\", \"P1\")\n");
  CHECK(p->diags.all().empty());
  const auto& h = p->stmt<ast::ElementStmt>(0);
  const auto* t = p->table(h.keys[0].value);
  REQUIRE(t != nullptr);
  CHECK(t->file.text == "power.csv");
  CHECK(t->column.text == "P1");
  CHECK(p->text_of(t->column) == "\"P1\"");
}

TEST_CASE("parser: series and parallel blocks") {
  auto p = parse("series mount plate2 ambient { contact h = 2500 A = 30e-4 ; conduction k = 0.25 "
                 "L = 3 [mm] A = 54.8 [mm^2] }\n"
                 "parallel par a b {\n  conductance G = 1\n\n  resistor R = 2 ;\n}\n");
  CHECK(p->diags.all().empty());
  const auto& s = p->stmt<ast::CompositeStmt>(0);
  CHECK(s.mode.name == "series");
  CHECK(s.name.id.name == "mount");
  REQUIRE(s.nodes.size() == 2);
  CHECK(s.nodes[0].id.name == "plate2");
  CHECK(s.nodes[1].id.name == "ambient");
  REQUIRE(s.parts.size() == 2);
  CHECK(s.parts[0].kind.name == "contact");
  CHECK(s.parts[0].keys.size() == 2);
  CHECK(s.parts[1].kind.name == "conduction");
  CHECK(s.parts[1].keys.size() == 3);
  CHECK(p->text_of(s.parts[1].keys[1]) == "L = 3 [mm]");
  const auto& q = p->stmt<ast::CompositeStmt>(1);
  CHECK(q.mode.name == "parallel");
  REQUIRE(q.parts.size() == 2);
  CHECK(q.parts[1].kind.name == "resistor");
  CHECK(p->where(q.begin) == "2:1");
}

TEST_CASE("parser: case block with every kind of setting") {
  auto p = parse("case warmup {\n  duration = 3 [h]\n  initial = steady\n  output = 10\n"
                 "  film.P = step(0: 10, 2500: 0)\n  ambient.T = 20\n  h_gap = 3\n"
                 "  data \"warmup.csv\"\n}\n");
  CHECK(p->diags.all().empty());
  const auto& c = p->stmt<ast::CaseStmt>(0);
  CHECK(c.name.name == "warmup");
  CHECK(p->text_of(c.name) == "warmup");
  REQUIRE(c.items.size() == 7);
  const auto* d = std::get_if<ast::CaseAssign>(&c.items[0]);
  REQUIRE(d != nullptr);
  CHECK(d->target.path.id.name == "duration");
  CHECK(d->target.path.rest().empty());
  CHECK(p->where(d->begin) == "2:3");
  const auto* film = std::get_if<ast::CaseAssign>(&c.items[3]);
  REQUIRE(film != nullptr);
  CHECK(film->target.path.id.name == "film");
  REQUIRE(film->target.path.rest().size() == 1);
  CHECK(film->target.path.rest()[0].id.name == "P");
  CHECK(p->text_of(film->target) == "film.P");
  CHECK(p->point_signal(film->value) != nullptr);
  const auto* param = std::get_if<ast::CaseAssign>(&c.items[5]);
  REQUIRE(param != nullptr);
  CHECK(param->target.path.id.name == "h_gap");
  const auto* data = std::get_if<ast::CaseData>(&c.items[6]);
  REQUIRE(data != nullptr);
  CHECK(data->path.text == "warmup.csv");
  CHECK(p->where(c.end) == "9:2");
}

TEST_CASE("parser: the spec's example parses without a diagnostic") {
  auto p = parse(thermnet::test::spec_example);
  CHECK(p->codes().empty());
  CHECK(p->file.statements.size() == 10);
  CHECK(p->file.unparsed.empty());
  CHECK(p->file.syntax_errors == 0);
}

TEST_CASE("parser: keywords are reserved only where a keyword is expected") {
  auto p = parse("node node2 C = 1\nparam range = 2 range 1 .. 3\nconst data = 1\n"
                 "const table = 2\nconst step = table * step\nconductance series1 node2 b G = 1\n"
                 "case c {\n  data = 3\n  data.T = 1\n  duration = 1\n}\n");
  CHECK(p->codes().empty());
  CHECK(p->stmt<ast::NodeStmt>(0).name.id.name == "node2");
  const auto& r = p->stmt<ast::ParamStmt>(1);
  CHECK(r.name.name == "range");
  CHECK(r.range.has_value());
  CHECK(p->stmt<ast::ElementStmt>(5).name.id.name == "series1");
  const auto& c = p->stmt<ast::CaseStmt>(6);
  REQUIRE(c.items.size() == 3);
  const auto* a = std::get_if<ast::CaseAssign>(&c.items[0]);
  REQUIRE(a != nullptr);
  CHECK(a->target.path.id.name == "data");
  const auto* b = std::get_if<ast::CaseAssign>(&c.items[1]);
  REQUIRE(b != nullptr);
  CHECK(b->target.path.rest()[0].id.name == "T");
}

// -----------------------------------------------------------------------------------------
// Lexical rules

TEST_CASE("parser: ';' separates statements and '\\' continues a line") {
  auto p =
      parse("node a C = 1 ; node b C = 2;node c C = 3\nconduction g a b \\\n  k = 1 L = 1 \\  \n"
            "  A = 1\n");
  CHECK(p->codes().empty());
  REQUIRE(p->file.statements.size() == 4);
  CHECK(p->where(p->stmt<ast::NodeStmt>(1).begin) == "1:16");
  CHECK(p->where(p->stmt<ast::NodeStmt>(2).begin) == "1:29");
  CHECK(p->stmt<ast::ElementStmt>(3).keys.size() == 3);
}

TEST_CASE("parser: newlines and comments inside ( ) and [ ] do not end a statement") {
  auto p = parse("const x = max(1,  # first\n   2,\n   3)\nconst y = 2 [W/(m^2\n*K)]\n"
                 "const z = 1\n");
  CHECK(p->codes().empty());
  REQUIRE(p->file.statements.size() == 3);
  CHECK(p->stmt<ast::ConstStmt>(2).name.name == "z");
  CHECK(value("max(1,\n 2)") == 2);
}

TEST_CASE("parser: comments, blank lines, CRLF, tabs and a byte order mark") {
  auto p = parse("\xEF\xBB\xBF# header\r\n\r\nnode\ta\tC = 1 # trailing\r\n  \t\r\n"
                 "node b C = 2\r\n");
  CHECK(p->codes().empty());
  REQUIRE(p->file.statements.size() == 2);
  CHECK(p->where(p->stmt<ast::NodeStmt>(1).begin) == "5:1");
}

TEST_CASE("parser: strings keep UTF-8 and resolve escapes") {
  auto p = parse("node a C = 1 \"W\xC3\xA4rme \\\"inner\\\" \\\\ \xE2\x88\x86T\"\n");
  CHECK(p->codes().empty());
  const auto& n = p->stmt<ast::NodeStmt>(0);
  REQUIRE(n.doc != nullptr);
  CHECK(n.doc->text == "W\xC3\xA4rme \"inner\" \\ \xE2\x88\x86T");
}

// -----------------------------------------------------------------------------------------
// Expressions

TEST_CASE("expressions: precedence and associativity") {
  CHECK(value("2^3^2") == 512);
  CHECK(value("-2^2") == -4);
  CHECK(value("1 - 2 - 3") == -4);
  CHECK(value("8/4/2") == 1);
  CHECK(value("2 + 3 * 4") == 14);
  CHECK(value("(2 + 3) * 4") == 20);
  CHECK(value("2 * 3 ^ 2") == 18);
  CHECK(value("2 ^ -1") == 0.5);
  CHECK(value("--2") == 2);
  CHECK(value("-(2 - 5)") == 3);
  CHECK(value("2^-1^2") == 0.5);
  CHECK(value("12 - 6 / 3 * 2") == 8);
}

TEST_CASE("expressions: number forms") {
  CHECK(value("12") == 12);
  CHECK(value("-3.5") == -3.5);
  CHECK(value("1e-3") == doctest::Approx(1e-3));
  CHECK(value("2.5E+4") == 25000);
  CHECK(value(".5") == 0.5);
}

TEST_CASE("expressions: constants and functions") {
  CHECK(value("pi") == doctest::Approx(std::numbers::pi));
  Quantity s = eval("sigma");
  CHECK(s.value == doctest::Approx(5.670374419e-8));
  REQUIRE(s.dim.has_value());
  CHECK(describe(*s.dim) == describe(dim::power / dim::area / dim::temperature.pow(4)));
  CHECK(value("sqrt(16)") == 4);
  CHECK(value("exp(0)") == 1);
  CHECK(value("log(exp(2))") == doctest::Approx(2));
  CHECK(value("log10(1000)") == doctest::Approx(3));
  CHECK(value("sin(pi / 2)") == doctest::Approx(1));
  CHECK(value("cos(0)") == 1);
  CHECK(value("tan(0)") == 0);
  CHECK(value("abs(-3)") == 3);
  CHECK(value("min(3, 1, 2)") == 1);
  CHECK(value("max(3, 1, 2)") == 3);
  CHECK(value("pow(2, 10)") == 1024);
}

TEST_CASE("expressions: units convert to SI and carry dimensions") {
  Quantity q = eval("3 [mm] * 2");
  CHECK(q.value == doctest::Approx(0.006));
  REQUIRE(q.dim.has_value());
  CHECK(*q.dim == dim::length);
  CHECK(eval("20 [degC]").value == doctest::Approx(293.15));
  CHECK(*eval("20 [degC]").dim == dim::temperature);
  CHECK(eval("293.15 [K]").value == doctest::Approx(293.15));
  // The sign belongs to the number: -10 [degC] is 263.15 K, not -(283.15 K).
  CHECK(eval("-10 [degC]").value == doctest::Approx(263.15));
  CHECK(eval("--10 [degC]").value == doctest::Approx(283.15));
  CHECK(eval("-3 [mm]").value == doctest::Approx(-0.003));
  CHECK(eval("2 * -3 [mm]").value == doctest::Approx(-0.006));
  CHECK(eval("1.5 [h]").value == doctest::Approx(5400));
  CHECK(*eval("1.5 [h]").dim == dim::time);
  CHECK(eval("2500 [s]").value == 2500);
  CHECK(eval("54.8 [mm^2]").value == doctest::Approx(54.8e-6));
  CHECK(*eval("160 [W/(m*K)]").dim == dim::conductivity);
  CHECK(*eval("2 [m] * 3 [m]").dim == dim::area);
  CHECK(*eval("sqrt(4 [m^2])").dim == dim::length);
  CHECK(eval("sqrt(4 [m^2])").value == doctest::Approx(2));
  CHECK(*eval("(2 [m])^2").dim == dim::area);
  CHECK(*eval("1 [W] / 2 [K]").dim == dim::conductance);
  CHECK_FALSE(eval("2 * 3").dim.has_value());
  CHECK(eval("1 [mm] + 2 [m]").value == doctest::Approx(2.001));
}

TEST_CASE("expressions: errors by code") {
  CHECK(eval_error("1 [m] + 1 [s]") == "unit-mismatch");
  CHECK(eval_error("max(1 [m], 1 [s])") == "unit-mismatch");
  CHECK(eval_error("2 [m] ^ 0.5") == "bad-argument");
  CHECK(eval_error("2 ^ (1 [m])") == "bad-argument");
  CHECK(eval_error("sin(1 [m])") == "bad-argument");
  CHECK(eval_error("sqrt(1 [m])") == "bad-argument");
  CHECK(eval_error("pow(1)") == "bad-argument");
  CHECK(eval_error("sqr(2)") == "unknown-function");
  CHECK(eval_error("1 / 0") == "invalid-value");
  CHECK(eval_error("log(0)") == "invalid-value");
  CHECK(eval_error("1 [furlong]") == "unknown-unit");
  CHECK(eval_error("nope") == "unknown-name");
  CHECK(eval_error("2 * 3") == "");
}

TEST_CASE("expressions: deep chains do not recurse") {
  std::string minus(100000, '-');
  CHECK(value(minus + "1") == 1);
  std::string sum = "1";
  for (int i = 0; i < 10000; ++i)
    sum += " + 1";
  CHECK(value(sum) == 10001);
}

// -----------------------------------------------------------------------------------------
// Syntax errors: location, message code, recovery

TEST_CASE("syntax errors are reported at the failing character") {
  struct Case {
    std::string text;
    const char* at;
    const char* mark;
    const char* code;
  };
  const Case cases[] = {
      {"node b C 1\n", "1:10", "1", "syntax"},
      {"node a C = 1 T0\n", "1:16", "", "syntax"},
      {"node a C = \n", "1:12", "", "syntax"},
      {"node a C = 3mm\n", "1:12", "3mm", "syntax"},
      {"node a C = 1.2.3\n", "1:12", "1.2.3", "syntax"},
      {"@@@ garbage\n", "1:1", "@", "syntax"},
      {"node a C = 1 \"open\n", "1:14", "\"open", "syntax"},
      {"node a C = (1 + 2\n", "1:18", "", "syntax"},
      {"node a C = 1 [J/K\n", "1:18", "", "syntax"},
      {"heater h n P = step(0: 1,)\n", "1:26", ")", "syntax"},
      {"heater h n P = step(0: 1, 2 3)\n", "1:29", "3", "syntax"},
      {"const x = max(1, )\n", "1:18", ")", "syntax"},
      {"}\n", "1:1", "}", "syntax"},
      {"node a C = 1 }\n", "1:14", "}", "syntax"},
      {"case c duration = 1\n", "1:8", "duration", "syntax"},
      {"case {\n}\n", "1:6", "{", "syntax"},
      {"case c {\n  duration 3\n}\n", "2:12", "3", "syntax"},
      {"case c {\n  data file.csv\n}\n", "2:8", "file.csv", "syntax"},
      {"case c {\n  duration = 1\n", "1:8", "{", "unterminated-block"},
      {"series s a b { conductance G = 1\n", "1:14", "{", "unterminated-block"},
      {"const x = " + std::string(65, '(') + "1" + std::string(65, ')') + "\n", "1:75", "(",
       "nesting-too-deep"},
      {"node a C = 1 \"\xC3\x28\"\n", "1:15", "\xC3", "invalid-encoding"},
  };
  for (const auto& c : cases) {
    INFO("input: ", c.text);
    auto p = parse(c.text);
    REQUIRE(!p->diags.all().empty());
    CHECK(p->diags.all().front().code == c.code);
    CHECK(p->first_at() == c.at);
    CHECK(p->first_mark() == c.mark);
  }
}

TEST_CASE("syntax errors: messages name what was expected and what was found") {
  auto p = parse("node b C 1\nnode c C = 3mm\n");
  REQUIRE(p->diags.all().size() == 2);
  CHECK(p->diags.all()[0].message == "expected '=', found '1'");
  CHECK(p->diags.all()[1].message == "expected value, found '3mm'");
  REQUIRE(p->diags.all()[1].notes.size() == 1);
  CHECK(p->diags.all()[1].notes[0].message ==
        "a unit goes in square brackets after the number: '3 [mm]'");
  auto q = parse("node a C = 1 \"open\n");
  CHECK(q->diags.all().front().message == "unterminated string");
}

TEST_CASE("syntax errors: every broken statement is reported and the rest is parsed") {
  auto p = parse("node a C = 1\nnode b C 1\n@@@\nnode c C = 2\n}\nconductance g a c G = = 1\n"
                 "case k {\n  duration 1\n  film.P = 3\n}\nnode d C = 4\n");
  CHECK(p->codes() == std::vector<std::string>{"syntax", "syntax", "syntax", "syntax", "syntax"});
  // Parsed: a, c, the case (with its one good item) and d.
  REQUIRE(p->file.statements.size() == 4);
  CHECK(p->stmt<ast::NodeStmt>(1).name.id.name == "c");
  CHECK(p->stmt<ast::CaseStmt>(2).items.size() == 1);
  CHECK(p->stmt<ast::NodeStmt>(3).name.id.name == "d");
  // The broken declarations keep the names they meant to declare.
  REQUIRE(p->file.unparsed.size() == 3);
  CHECK(p->file.unparsed[0].head.name == "node");
  CHECK(p->file.unparsed[0].name.name == "b");
  CHECK(p->file.unparsed[2].head.name == "conductance");
  CHECK(p->file.unparsed[2].name.name == "g");
  CHECK(p->file.syntax_errors == 5);
}

TEST_CASE("syntax errors: an unclosed '(' ends at its own line") {
  auto p = parse("const x = (1 + 2\nnode b C = 1\n");
  CHECK(p->codes() == std::vector<std::string>{"syntax"});
  REQUIRE(p->file.statements.size() == 1);
  CHECK(p->stmt<ast::NodeStmt>(0).name.id.name == "b");
}

TEST_CASE("syntax errors: the error limit stops the parser and says so") {
  std::string text;
  for (int i = 0; i < 1000; ++i)
    text += "node a" + std::to_string(i) + " C = = 1\n";
  SourceManager sm;
  DiagnosticEngine diags(sm, 20);
  FileId id = sm.add("t.tnet", text);
  parse_file(id, sm, diags);
  REQUIRE(diags.all().size() == 21);
  CHECK(diags.all().back().code == "too-many-errors");
}

TEST_CASE("syntax errors: NUL bytes and invalid UTF-8 reject the file") {
  auto p = parse(std::string("node a C = 1\0\n", 14));
  CHECK(p->codes() == std::vector<std::string>{"invalid-encoding"});
  CHECK(p->file.statements.empty());
  auto q = parse("# \xFF\xFE\n");
  CHECK(q->codes() == std::vector<std::string>{"invalid-encoding"});
  // A backslash before a multi-byte character is a syntax error (only \" and \\ are escapes),
  // not an encoding error.
  auto r = parse("node a C = 1 \"a\\\xC3\xA9\"\n");
  CHECK(r->codes() == std::vector<std::string>{"syntax"});
}

// -----------------------------------------------------------------------------------------
// Extensions: loops, submodels, indexed and dotted names, lists, data units

TEST_CASE("parser: for blocks with several variables, nested, with indexed names") {
  auto p = parse("for i in 1 .. n - 1, j in i..3\n{\n  node p[i, j + 1] C = 1\n"
                 "  for k in 0 .. 2 { conductance g[i,k] p[i, 1] u[2].q[k] G = 1 }\n}\n");
  CHECK(p->codes().empty());
  const auto& f = p->stmt<ast::ForStmt>(0);
  REQUIRE(f.ranges.size() == 2);
  CHECK(f.ranges[0].var.name == "i");
  CHECK(p->text_of(f.ranges[0].hi) == "n - 1");
  CHECK(p->text_of(f.ranges[1].lo) == "i");
  REQUIRE(f.body.size() == 2);
  const auto* n = std::get_if<ast::NodeStmt>(&f.body[0]);
  REQUIRE(n != nullptr);
  CHECK(n->name.id.name == "p");
  REQUIRE(n->name.index().size() == 2);
  CHECK(p->text_of(n->name.index()[1]) == "j + 1");
  const auto* inner = std::get_if<ast::ForStmt>(&f.body[1]);
  REQUIRE(inner != nullptr);
  const auto* g = std::get_if<ast::ElementStmt>(&inner->body[0]);
  REQUIRE(g != nullptr);
  REQUIRE(g->nodes.size() == 2);
  const ast::Ref& q = g->nodes[1];
  CHECK(p->text_of(q) == "u[2].q[k]");
  REQUIRE(q.rest().size() == 1);
  CHECK(q.rest()[0].id.name == "q");
  CHECK(q.rest()[0].index().size() == 1);
  CHECK(p->where(f.end) == "5:2");
}

TEST_CASE("parser: a declared range of indices and a statement named like the new keywords") {
  auto p = parse("node p[1 .. 10, 2] C = 1\nconductance for in out G = 1\nnode submodel C = 1\n");
  CHECK(p->codes().empty());
  const auto& n = p->stmt<ast::NodeStmt>(0);
  REQUIRE(n.name.index().size() == 2);
  REQUIRE(n.name.index()[0].hi.has_value());
  CHECK(p->text_of(*n.name.index()[0].hi) == "10");
  CHECK_FALSE(n.name.index()[1].hi.has_value());
  // `for` and `submodel` are keywords only where their blocks start.
  CHECK(p->stmt<ast::ElementStmt>(1).name.id.name == "for");
  CHECK(p->stmt<ast::NodeStmt>(2).name.id.name == "submodel");
  // An element of a plugin kind called `for` still reads as an element.
  auto q = parse("for x in a b G = 1\n");
  CHECK(q->codes().empty());
  CHECK(q->stmt<ast::ElementStmt>(0).kind.name == "for");
}

TEST_CASE("parser: submodel definitions and their params without a value") {
  auto p = parse("submodel box(mount, lid) {\n  param P\n  param h = 3 \"coefficient\"\n"
                 "  node wall C = 1\n}\nsubmodel empty() {\n}\nbox b1 a c P = 2\n");
  CHECK(p->codes().empty());
  const auto& s = p->stmt<ast::SubmodelStmt>(0);
  CHECK(s.name.name == "box");
  REQUIRE(s.terminals.size() == 2);
  CHECK(s.terminals[1].name == "lid");
  REQUIRE(s.body.size() == 3);
  CHECK_FALSE(std::get<ast::ParamStmt>(s.body[0]).value.valid());
  CHECK(std::get<ast::ParamStmt>(s.body[1]).value.valid());
  CHECK(p->stmt<ast::SubmodelStmt>(1).terminals.empty());
  CHECK(p->stmt<ast::ElementStmt>(2).kind.name == "box");
  // Outside a submodel a param needs its value.
  CHECK(parse("param P\n")->codes() == std::vector<std::string>{"syntax"});
}

TEST_CASE("parser: case settings with loops, dotted targets, lists and a data unit") {
  auto p = parse("case c {\n  output = 0, 100 [s], 250\n  u1.pcb.T0 = 30\n"
                 "  for i in 1 .. 3 { h[i].P = i }\n  data \"run.csv\" [K]\n}\n");
  CHECK(p->codes().empty());
  const auto& c = p->stmt<ast::CaseStmt>(0);
  REQUIRE(c.items.size() == 4);
  const auto& out = std::get<ast::CaseAssign>(c.items[0]);
  REQUIRE(out.more.size() == 2);
  CHECK(p->text_of(out.more[0]) == "100 [s]");
  const auto& t0 = std::get<ast::CaseAssign>(c.items[1]);
  CHECK(p->text_of(t0.target) == "u1.pcb.T0");
  CHECK(t0.target.path.rest().size() == 2);
  const auto& loop = std::get<ast::CaseFor>(c.items[2]);
  REQUIRE(loop.items.size() == 1);
  CHECK(p->text_of(std::get<ast::CaseAssign>(loop.items[0]).target) == "h[i].P");
  const auto& data = std::get<ast::CaseData>(c.items[3]);
  REQUIRE(data.unit.has_value());
  CHECK(data.unit->text == "K");
}

TEST_CASE("parser: a node reference as a value, and an index must follow its name") {
  auto p = parse("thermostat t n P = 5 on = 18 off = 22 sense = p[3]\n");
  CHECK(p->codes().empty());
  const auto* r = p->stmt<ast::ElementStmt>(0).keys[3].value.as_reference();
  REQUIRE(r != nullptr);
  CHECK(p->text_of(*r) == "p[3]");
  // `x [K]` is not an index (nor a unit: units follow numbers).
  CHECK(parse("const y = x [K]\n")->codes() == std::vector<std::string>{"syntax"});
}

TEST_CASE("parser: signals and key references stand in expressions") {
  auto p = parse("heater sun n P = Aw * table(\"w.csv\", \"I_sol\", hold, time = \"t\" [h], "
                 "separator = \";\") [W/m^2] + 0.5 * film.P + pwl(0: 1, 10: 2)\n"
                 "heater copy n P = film.P\n");
  CHECK(p->diags.all().empty());
  const auto& h = p->stmt<ast::ElementStmt>(0);
  REQUIRE(p->file.signals.size() == 2);
  const auto* t = std::get_if<ast::TableSignal>(&p->file.signals[0]);
  REQUIRE(t != nullptr);
  CHECK(t->hold);
  CHECK_FALSE(t->case_data);
  REQUIRE(t->options.time);
  CHECK(t->options.time->column.text == "t");
  REQUIRE(t->options.time->unit);
  CHECK(t->options.time->unit->text == "h");
  REQUIRE(t->options.separator);
  CHECK(t->options.separator->text == ";");
  REQUIRE(t->unit);
  CHECK(t->unit->text == "W/m^2");
  CHECK(p->text_of(*t).ends_with("[W/m^2]"));
  REQUIRE(p->file.expr_refs.size() == 1);
  CHECK(p->text_of(p->file.expr_refs[0]) == "film.P");
  CHECK(std::holds_alternative<ast::PointSignal>(p->file.signals[1]));
  CHECK(p->signal(h.keys[0].value) == nullptr); // an expression of signals, not one signal
  const auto& copy = p->stmt<ast::ElementStmt>(1);
  REQUIRE(copy.keys[0].value.as_reference() != nullptr);
  CHECK(p->text_of(*copy.keys[0].value.as_reference()) == "film.P");
}

TEST_CASE("parser: table(data, ...), a data statement's layout and column map, mean terminals") {
  auto p = parse("boundary room T = table(data, \"t1\")\n"
                 "sensor probe mean(a, b[2]) tau = 3\n"
                 "case c {\n"
                 "  data \"run.csv\" [K] time = \"stamp\" [unix ns] separator = \";\" {\n"
                 "    air = mean(t2, \"t 3\": 2) [degF]\n"
                 "    room = t1\n"
                 "  }\n"
                 "  w.T0 = 20 range 10 .. 30\n"
                 "}\n");
  INFO(render_text(p->diags));
  CHECK(p->diags.all().empty());
  const auto* t = p->table(p->stmt<ast::NodeStmt>(0).keys[0].value);
  REQUIRE(t != nullptr);
  CHECK(t->case_data);
  const auto& s = p->stmt<ast::ElementStmt>(1);
  CHECK(s.mean);
  REQUIRE(s.nodes.size() == 2);
  CHECK(p->text_of(s.nodes[1]) == "b[2]");
  const auto& c = p->stmt<ast::CaseStmt>(2);
  const auto* d = std::get_if<ast::CaseData>(&c.items[0]);
  REQUIRE(d != nullptr);
  REQUIRE(d->unit);
  CHECK(d->unit->text == "K");
  REQUIRE(d->options.time);
  CHECK(d->options.time->unit->text == "unix ns");
  CHECK(d->mapped);
  REQUIRE(d->columns.size() == 2);
  CHECK(d->columns[0].mean);
  REQUIRE(d->columns[0].sources.size() == 2);
  CHECK(d->columns[0].sources[1].column.text == "t 3");
  REQUIRE(d->columns[0].sources[1].weight);
  CHECK(d->columns[0].unit->text == "degF");
  CHECK(d->columns[1].sources[0].column.text == "t1");
  const auto* a = std::get_if<ast::CaseAssign>(&c.items[1]);
  REQUIRE(a != nullptr);
  REQUIRE(a->range != nullptr);
  CHECK(p->text_of(*a->range) == "10 .. 30");
}
