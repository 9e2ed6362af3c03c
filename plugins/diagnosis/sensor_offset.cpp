// Hypothesis 'sensor_offset': a sensor reads its node with a constant bias. Measurement-side: the
// correction is added to the simulated series; the start is the mean residual.
#include "kernel/diagnosis/hypothesis.hpp"
#include "kernel/diagnosis/sensor_statements.hpp"

#include <fmt/format.h>

#include <cmath>

namespace thermnet {
namespace {

class SensorOffset final : public Hypothesis {
public:
  std::vector<Candidate> propose(const Evidence& ev) const override {
    std::vector<Candidate> out;
    if (ev.cases.empty()) return out;
    const auto& nodes = ev.cases.front().spec.nodes;
    for (int a = 0; a < static_cast<int>(nodes.size()); ++a) {
      if (nodes[static_cast<std::size_t>(a)].boundary) continue;
      double sum = 0.0;
      std::size_t n = 0;
      for (const auto& ce : ev.cases)
        for (std::size_t s = 0; s < ce.measured.series.size(); ++s) {
          if (ce.measured.series[s].node_index != a) continue;
          for (std::size_t k = 0; k < ce.times().size(); ++k)
            if (!std::isnan(ce.measured.series[s].values[k]))
              sum += ce.measured.series[s].values[k] - ce.simulated[s][k], ++n;
        }
      if (n == 0) continue;
      Candidate c;
      c.kind = "sensor_offset";
      c.nodes = {nodes[static_cast<std::size_t>(a)].name};
      c.names = {"offset"};
      c.lo = {-100.0};
      c.hi = {100.0};
      c.start = {sum / static_cast<double>(n)};
      c.measurement_side = true;
      c.screen = sum * sum / static_cast<double>(n);
      c.index = {a};
      c.evidence = fmt::format("{} reads {:.3g} K {} than simulated on average", c.nodes[0],
                               std::abs(c.start[0]), c.start[0] >= 0 ? "higher" : "lower");
      out.push_back(std::move(c));
    }
    return out;
  }

  void correct(const Candidate& c, const std::vector<double>& p, int node,
               const std::vector<double>&, std::vector<double>& sim) const override {
    if (node != c.index[0]) return;
    for (double& v : sim)
      v += p[0];
  }

  std::string statement(const Candidate& c, const std::vector<double>& p,
                        const Evidence& ev) const override {
    return sensor_statement(ev, "sensor_offset", c.nodes[0], "offset", p[0], "K");
  }

  CaseLines case_statements(const Candidate& c, const std::vector<double>& p,
                            const Evidence& ev) const override {
    return sensor_case_lines(ev, c.nodes[0], "offset", p[0], "K");
  }
};

HypothesisPlugin make_sensor_offset() {
  return {.name = "sensor_offset",
          .doc = "a sensor reads with a constant bias (K)",
          .create = [] { return std::make_unique<SensorOffset>(); },
          .screen = "the mean residual (fitted directly)",
          .fitted = "offset [K]",
          .writes = "sensor diag_sensor_offset_a a offset = ... (or the key of a sensor the model "
                    "has, in every case)"};
}

} // namespace
THERMNET_REGISTER(HypothesisPlugin, make_sensor_offset);
} // namespace thermnet
