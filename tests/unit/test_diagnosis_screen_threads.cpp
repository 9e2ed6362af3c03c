// The diagnosis on several threads: the kinds propose at the same time, missing_link spreads its
// pairs and wall_mass its links over Evidence::threads, and the candidates are judged in
// parallel; the candidates, their scores and their order, and the whole report, must be those of
// one thread.

#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/diagnosis/engine.hpp"
#include "kernel/diagnosis/report.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

namespace {

using namespace thermnet;
using namespace thermnet::detail;

/// A chain of 12 nodes in air, every other one measured, a heater at each end; {EXTRA} takes the
/// truth's hidden link and {DATA} the data statement.
std::string chain(const std::string& extra, const std::string& data) {
  std::string text = "model chain\nboundary air T = 20\n";
  for (int i = 0; i < 12; ++i) {
    text += fmt::format("node n{} C = {} [J/K] T0 = 20\n", i, 300 + 20 * i);
    text += fmt::format("convection c{} n{} air h = 8 A = 0.01\n", i, i);
    if (i > 0) text += fmt::format("conductance g{} n{} n{} G = 0.4\n", i, i - 1, i);
  }
  text += "heater q0 n0 P = 0\nheater q11 n11 P = 0\n" + extra + "\n";
  text += "case run { duration = 7200; output = 60; q0.P = step(0: 4, 3000: 1); "
          "q11.P = step(0: 0, 1800: 3)" +
          data + " }\n";
  return text;
}

/// The data of the even nodes: the chain with a hidden link n2 -- n9, in degC.
void write_data(const test::TempDir& dir) {
  test::LoadedModel truth(dir.write("truth.tnet", chain("conductance hid n2 n9 G = 0.3", "")),
                          test::Lint::clean);
  Network net(truth.model->instantiate("run"));
  const SimulationResult r = simulate(net);
  std::string csv = "time";
  for (int i = 0; i < 12; i += 2)
    csv += fmt::format(",n{}", i);
  csv += "\n";
  for (std::size_t k = 0; k < r.times.size(); ++k) {
    csv += fmt::format("{}", r.times[k]);
    for (int i = 0; i < 12; i += 2)
      csv += fmt::format(
          ",{:.4f}",
          r.temps[k][static_cast<std::size_t>(net.spec().node_index(fmt::format("n{}", i)))] -
              273.15);
    csv += "\n";
  }
  dir.write("run.csv", csv);
}

/// What a candidate is, in words: kind, nodes, mechanism, start and screen score to the last bit.
std::vector<std::string> described(const std::vector<Candidate>& cs) {
  std::vector<std::string> out;
  for (const auto& c : cs)
    out.push_back(fmt::format("{} {} {} {} {} {}", c.kind, fmt::join(c.nodes, ","), c.mechanism,
                              fmt::join(c.start, ","), c.screen, c.evidence));
  return out;
}

} // namespace

TEST_CASE("diagnosis screen: the kinds that spread over threads propose the same on 1 and 4") {
  test::TempDir dir;
  write_data(dir);
  test::LoadedModel m(dir.write("model.tnet", chain("", "; data \"run.csv\"")), test::Lint::clean);
  // missing_link: 12 nodes and the air, 66 node pairs and 12 to the air, each linear and radiative
  // where the screen finds heat flowing the right way, or unscored between two unmeasured ends;
  // wall_mass: 11 conductances and 12 convections, those the screen finds a mass in
  for (const auto& [kind, least] : {std::pair{"missing_link", 40}, std::pair{"wall_mass", 3}}) {
    CAPTURE(kind);
    const std::unique_ptr<Hypothesis> h = HypothesisRegistry::global().find(kind)->create();
    std::vector<std::vector<std::string>> lists;
    for (int threads : {1, 4}) {
      DiagnosisOptions opt;
      opt.threads = threads;
      const Engine engine(*m.model, opt);
      CHECK(engine.evidence().threads == threads);
      lists.push_back(described(h->propose(engine.evidence())));
    }
    REQUIRE(lists[0].size() > static_cast<std::size_t>(least));
    CHECK(lists[1] == lists[0]);
  }
}

TEST_CASE("diagnosis: the report is the same on 1 and 3 threads") {
  test::TempDir dir;
  write_data(dir);
  test::LoadedModel m(dir.write("model.tnet", chain("", "; data \"run.csv\"")), test::Lint::clean);
  std::vector<nlohmann::json> reports;
  for (int threads : {1, 3}) {
    DiagnosisOptions opt;
    opt.threads = threads;
    nlohmann::json j = diagnosis_json(diagnose(*m.model, opt));
    for (const char* timing : {"wall_s", "cpu_s", "setup_wall_s", "batches"})
      j.erase(timing);
    reports.push_back(std::move(j));
  }
  REQUIRE(!reports[0]["findings"].empty());
  CHECK(reports[0]["findings"][0]["kind"] == "missing_link");
  CHECK(reports[1].dump() == reports[0].dump());
}
