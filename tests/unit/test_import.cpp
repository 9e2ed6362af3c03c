/// Unit tests of the import library's pieces: Fortran numbers, SPICE numbers and expressions,
/// format detection, and the Foster to Cauer conversion (checked in the time domain against an
/// eigendecomposition of the ladder, independently of the conversion's own s-domain check).

#include "import/fortran_number.hpp"
#include "import/foster_cauer.hpp"
#include "import/importer.hpp"
#include "import/report.hpp"
#include "import/spice_expression.hpp"
#include "import/spice_number.hpp"

#include <Eigen/Dense>
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

using namespace thermnet::importer;

TEST_CASE("import: Fortran reals as Fortran reads them") {
  const std::map<std::string, double> good = {
      {"1.0D3", 1000},    {"1.E-2", 0.01}, {"+.5", 0.5},      {"7", 7}, {"5.", 5},
      {"-1.5d-1", -0.15}, {"1Q2", 100},    {"2.5e+4", 25000}, {"-0", 0}};
  for (const auto& [text, value] : good) {
    INFO(text);
    const RealResult r = parse_fortran_real(text);
    CHECK(r.problem == NumberProblem::none);
    CHECK(r.value == doctest::Approx(value).epsilon(1e-15));
  }
  for (const char* text : {"1.0E", "E5", ".", "1.2.3", "0x10", "1.0+3", "", "+", "1 0", "inf",
                           "nan", "1,0", "1.0D", "--1", "1e5.0", "1.0F3", "+-1"}) {
    INFO(text);
    CHECK(parse_fortran_real(text).problem == NumberProblem::malformed);
  }
  CHECK(parse_fortran_real("1e999").problem == NumberProblem::out_of_range);
  CHECK(parse_fortran_real("-1.0D400").problem == NumberProblem::out_of_range);
  // Too small to be a double: an error, not a silent 0 (a capacity gone).
  CHECK(parse_fortran_real("1e-400").problem == NumberProblem::underflow);
  CHECK(parse_fortran_real("1.0D-400").problem == NumberProblem::underflow);
  CHECK(fortran_number_message("1.0D-400", NumberProblem::underflow).find("underflows") !=
        std::string::npos);
}

TEST_CASE("import: Fortran integers") {
  CHECK(parse_fortran_integer("63") == 63);
  CHECK(parse_fortran_integer("+63") == 63);
  CHECK(parse_fortran_integer("-3") == -3);
  for (const char* text : {"1.0", "+-3", "", "1e3", "63a", "99999999999999999999"})
    CHECK_FALSE(parse_fortran_integer(text).has_value());
}

TEST_CASE("import: SPICE numbers, their suffixes and unit letters") {
  const std::map<std::string, double> good = {
      {"1k", 1e3},   {"10meg", 1e7}, {"10MEG", 1e7}, {"2.2u", 2.2e-6}, {"1mil", 25.4e-6},
      {"1uF", 1e-6}, {"10Ohm", 10},  {"1e3", 1e3},   {"4.7K", 4.7e3},  {"3ms", 3e-3},
      {"1F", 1e-15}, {"2g", 2e9},    {"1t", 1e12},   {"5p", 5e-12},    {"-1.5n", -1.5e-9}};
  for (const auto& [text, value] : good) {
    INFO(text);
    auto n = spice::spice_number(text);
    REQUIRE(n.has_value());
    CHECK(n->value == doctest::Approx(value).epsilon(1e-15));
  }
  CHECK(spice::spice_number("1F")->femto_alone);
  CHECK_FALSE(spice::spice_number("1fF")->femto_alone);
  CHECK_FALSE(spice::spice_number("1uF")->femto_alone);
  // Below the smallest double, as written or once the suffix applies: flagged, not a quiet 0.
  for (const char* text : {"1e-400", "1e-320f", "-3e-330p"}) {
    INFO(text);
    REQUIRE(spice::spice_number(text).has_value());
    CHECK(spice::spice_number(text)->underflow);
  }
  CHECK_FALSE(spice::spice_number("1e-300")->underflow);
  CHECK_FALSE(spice::spice_number("0f")->underflow);
  for (const char* text : {"abc", "1k2", "k", "", "1.2.3", "1e999"})
    CHECK_FALSE(spice::spice_number(text).has_value());
}

namespace {

double eval(const std::string& text, const std::map<std::string, double>& params = {}) {
  return spice::evaluate(text, 0, 0, [&](const std::string& n) -> std::optional<double> {
    auto it = params.find(n);
    return it == params.end() ? std::nullopt : std::optional<double>(it->second);
  });
}

} // namespace

TEST_CASE("import: SPICE expressions") {
  CHECK(eval("2*3+4") == 10);
  CHECK(eval("2^3^2") == 512);
  CHECK(eval("2**3") == 8);
  CHECK(eval("-(1+2)*2") == -6);
  CHECK(eval("sqrt(16) + max(1, 5, 3) - min(2, 7)") == 7);
  CHECK(eval("log(100)") == doctest::Approx(std::log(100.0))); // natural, as in ngspice
  CHECK(eval("log10(100)") == doctest::Approx(2));
  CHECK(eval("2k * r / 4", {{"r", 3}}) == 1500);
  CHECK(eval("tau/ rth", {{"tau", 1e-3}, {"rth", 0.02}}) == doctest::Approx(0.05));
  const auto code_of = [](const std::string& text) {
    try {
      eval(text);
    } catch (const ImportError& e) {
      return e.code;
    }
    return std::string("none");
  };
  CHECK(code_of("rx * 2") == "unknown-param");
  CHECK(code_of("1/0") == "bad-expression");
  CHECK(code_of("sqrt(-1)") == "bad-expression");
  CHECK(code_of("2 +") == "bad-expression");
  CHECK(code_of("foo(1)") == "bad-expression");
  CHECK(code_of(std::string(100000, '(') + "1" + std::string(100000, ')')) == "bad-expression");
  CHECK(code_of(std::string(100000, '-') + "1") == "bad-expression");
}

TEST_CASE("import: SPICE expressions as thermnet text") {
  // Names: a subcircuit's params by name, a netlist's .param by its value (here), others none.
  const spice::NameText names = [](const std::string& n) -> std::optional<std::string> {
    if (n == "a" || n == "b" || n == "c") return n;
    if (n == "g") return std::string("-3");
    return std::nullopt;
  };
  const std::map<std::string, std::optional<std::string>> cases = {
      {"a*b+c", "a * b + c"},
      {"a-(b-c)", "a - (b - c)"},
      {"(a-b)-c", "(a - b) - c"},
      {"a/(b*c)", "a / (b * c)"},
      {"a/b*c", "a / b * c"},
      // SPICE's leading minus binds tighter than ^ (the evaluator's grammar), thermnet's looser:
      // the translation brackets it.
      {"-a^2", "(-a)^2"},
      {"-(a^2)", "-(a^2)"},
      {"2**3**2", "2^3^2"},
      {"a^-b", "a^(-b)"},
      {"g*a", "-3 * a"},
      {"a^g", "a^(-3)"},
      {"ln(a) + log(b)", "log(a) + log(b)"},
      {"max(a, 1k, 2meg)", "max(a, 1000, 2000000)"},
      {"pi*a", "pi * a"},
      {"{a}", std::nullopt},       // (braces belong to the card, not the expression)
      {"atan(a)", std::nullopt},   // no thermnet function
      {"pwr(a, 2)", std::nullopt}, // ngspice's pwr keeps the sign: not pow
      {"z * 2", std::nullopt},     // a name with no text
      {"a +", std::nullopt}};
  for (const auto& [spice_text, expected] : cases) {
    INFO(spice_text);
    CHECK(spice::translate(spice_text, names) == expected);
  }
}

TEST_CASE("import: the format is found from the content") {
  CHECK(detect_format("C deck\nHEADER NODE DATA, MAIN\n  1, 20, 1\n") == Format::sinda);
  CHECK(detect_format("* title\nR1 a 0 1k\nC1 a 0 1u\n.end\n") == Format::spice);
  CHECK(detect_format("title\n.subckt x a b\n.ends\n") == Format::spice);
  CHECK(detect_format("some words\nmore words\n") == Format::automatic);
  CHECK(detect_format("") == Format::automatic);
}

namespace {

/// Zth(t) of a Cauer ladder (far end held) by an eigendecomposition of its state matrix: the
/// temperature of node 1 per watt of a step into it.
double cauer_step(const std::vector<CauerStage>& s, double t) {
  const auto n = static_cast<Eigen::Index>(s.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double g = 1 / s[static_cast<std::size_t>(k)].R;
    K(k, k) += g;
    if (k + 1 < n) {
      K(k + 1, k + 1) += g;
      K(k, k + 1) -= g;
      K(k + 1, k) -= g;
    }
  }
  Eigen::VectorXd c(n);
  for (Eigen::Index k = 0; k < n; ++k)
    c(k) = s[static_cast<std::size_t>(k)].C;
  // C dT/dt = -K T + e1: symmetric form with x = C^1/2 T.
  const Eigen::VectorXd ci = c.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd A = ci.asDiagonal() * K * ci.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  double z = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lambda = es.eigenvalues()(i);
    const double w = es.eigenvectors()(0, i) * ci(0);
    z += w * w * -std::expm1(-lambda * t) / lambda;
  }
  return z;
}

void check_same_zth(const std::vector<FosterCell>& cells) {
  const std::vector<CauerStage> stages = foster_to_cauer(cells);
  double taus_min = 1e300, taus_max = 0, Rsum = 0, Cinv = 0;
  for (const auto& c : cells) {
    taus_min = std::min(taus_min, c.R * c.C);
    taus_max = std::max(taus_max, c.R * c.C);
    Rsum += c.R;
    Cinv += 1 / c.C;
  }
  double Rc = 0;
  for (const auto& s : stages) {
    CHECK(s.R > 0);
    CHECK(s.C > 0);
    Rc += s.R;
  }
  CHECK(Rc == doctest::Approx(Rsum).epsilon(1e-9));              // Z(0): the resistances add up
  CHECK(stages[0].C == doctest::Approx(1 / Cinv).epsilon(1e-9)); // Z(s) ~ 1/(s C1) at high s
  for (double t = taus_min / 100; t < taus_max * 100; t *= 1.7) {
    INFO("t = ", t);
    CHECK(cauer_step(stages, t) ==
          doctest::Approx(foster_step_response(cells, t)).epsilon(1e-7).scale(Rsum * 1e-9));
  }
}

} // namespace

TEST_CASE("import: a Foster network as a Cauer ladder has the same Zth(t)") {
  // One cell is its own ladder.
  const auto one = foster_to_cauer({{2.0, 3.0}});
  REQUIRE(one.size() == 1);
  CHECK(one[0].R == doctest::Approx(2.0));
  CHECK(one[0].C == doctest::Approx(3.0));
  // A datasheet's four cells (an IGBT module's junction to case).
  check_same_zth({{0.0121, 0.0827}, {0.0438, 0.2283}, {0.0873, 1.3746}, {0.0568, 17.6}});
  // Time constants spread over nine decades.
  std::vector<FosterCell> wide;
  for (int k = 0; k < 8; ++k)
    wide.push_back({0.01 * (k + 1), std::pow(10.0, k - 6) / (0.01 * (k + 1))});
  check_same_zth(wide);
  // Equal time constants are one cell.
  const auto merged = foster_to_cauer({{1.0, 2.0}, {3.0, 2.0 / 3.0}});
  REQUIRE(merged.size() == 1);
  CHECK(merged[0].R == doctest::Approx(4.0));
  CHECK(merged[0].C == doctest::Approx(0.5));
}

TEST_CASE("import: Foster networks that cannot be converted are refused") {
  CHECK_THROWS_AS(foster_to_cauer({}), FosterError);
  CHECK_THROWS_AS(foster_to_cauer({{0.0, 1.0}}), FosterError);
  CHECK_THROWS_AS(foster_to_cauer({{1.0, -1.0}}), FosterError);
  CHECK_THROWS_AS(foster_to_cauer({{std::numeric_limits<double>::quiet_NaN(), 1.0}}), FosterError);
  CHECK_THROWS_AS(foster_to_cauer({{1.0, std::numeric_limits<double>::infinity()}}), FosterError);
}
