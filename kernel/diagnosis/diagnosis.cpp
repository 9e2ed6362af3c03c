// Diagnosis helpers shared by the engine and the hypothesis plugins: the hypothesis registry,
// netlist text, the screen's regression, the noise estimate and smoothing; and the entry point.
// The engine is kernel/diagnosis_engine.cpp and diagnosis_select.cpp; the hypotheses live in
// plugins/diagnosis/.

#include "kernel/diagnosis/diagnosis.hpp"

#include "kernel/core/element_registry.hpp"
#include "kernel/diagnosis/engine.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace thermnet {

// ------------------------------------------------------------------------- registry, helpers

std::string netlist_number(double v) {
  return fmt::format("{:.5g}", v + 0.0); // + 0.0: no "-0"
}

void merge_case_lines(CaseLines& lines, const CaseLines& more) {
  for (const auto& [name, text] : more) {
    std::string& to = lines[name];
    to += (to.empty() ? "" : "\n") + text;
  }
}

lang::ElementSpec make_element(const std::string& kind, const std::string& name,
                               std::vector<int> nodes, const std::map<std::string, double>& keys) {
  lang::ElementSpec e;
  e.schema = element_catalog().find(kind);
  if (!e.schema) throw std::invalid_argument("no element kind '" + kind + "'");
  e.kind = kind;
  e.name = name;
  e.nodes = std::move(nodes);
  for (const auto& [k, v] : keys)
    e.values.emplace(k, lang::Signal::of(v));
  return e;
}

std::string unique_name(const lang::NetworkSpec& spec, const std::string& base) {
  auto taken = [&](const std::string& n) {
    if (spec.node_index(n) >= 0) return true;
    for (const auto& e : spec.elements)
      if (e.name == n) return true;
    return false;
  };
  std::string n = base;
  for (int i = 2; taken(n); ++i)
    n = fmt::format("{}_{}", base, i);
  return n;
}

ScreenFit Evidence::regress(
    const std::function<double(std::size_t c, int node, std::size_t k)>& basis) const {
  double qb = 0.0, bb = 0.0, qq = 0.0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const CaseEvidence& ce = cases[c];
    for (int node : ce.rows) {
      const double C = ce.spec.nodes[static_cast<std::size_t>(node)].C;
      for (std::size_t k = 0; k < ce.q.size(); ++k) {
        const double q = ce.q[k][static_cast<std::size_t>(node)];
        if (std::isnan(q)) continue;
        const double b = basis(c, node, k);
        if (!std::isfinite(b) || b == 0.0) {
          qq += q * q / (C * C);
          continue;
        }
        qb += q * b / (C * C);
        bb += b * b / (C * C);
        qq += q * q / (C * C);
      }
    }
  }
  ScreenFit f;
  if (bb <= 0.0) return f;
  f.coefficient = qb / bb;
  f.reduction = qb * qb / bb;
  f.correlation = qq > 0.0 ? qb / std::sqrt(bb * qq) : 0.0;
  return f;
}

int Evidence::node_index(const std::string& name) const {
  return cases.empty() ? -1 : cases.front().spec.node_index(name);
}

bool Evidence::measured(int node) const {
  for (const auto& c : cases)
    if (std::find(c.rows.begin(), c.rows.end(), node) != c.rows.end()) return true;
  return false;
}

double estimate_noise(const std::vector<double>& v) {
  std::vector<double> d;
  for (std::size_t k = 1; k + 1 < v.size(); ++k) {
    const double x = v[k + 1] - 2.0 * v[k] + v[k - 1];
    if (std::isfinite(x)) d.push_back(x);
  }
  if (d.size() < 5) return 0.0;
  auto median = [](std::vector<double> x) {
    std::nth_element(x.begin(), x.begin() + static_cast<long>(x.size() / 2), x.end());
    return x[x.size() / 2];
  };
  const double m = median(d);
  for (double& x : d)
    x = std::abs(x - m);
  return 1.4826 * median(d) / std::sqrt(6.0);
}

void smooth_series(const std::vector<double>& t, const std::vector<double>& v, int half,
                   std::vector<double>& smoothed, std::vector<double>& slope) {
  const std::size_t n = v.size();
  smoothed.assign(n, std::numeric_limits<double>::quiet_NaN());
  slope.assign(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a =
        k >= static_cast<std::size_t>(half) ? k - static_cast<std::size_t>(half) : 0;
    const std::size_t b = std::min(n - 1, k + static_cast<std::size_t>(half));
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    int used = 0;
    const double scale = std::max(1e-9, (t[b] - t[a]) / 2.0);
    for (std::size_t j = a; j <= b; ++j) {
      if (!std::isfinite(v[j])) continue;
      const double x = (t[j] - t[k]) / scale;
      const Eigen::Vector3d phi(1.0, x, x * x);
      A += phi * phi.transpose();
      y += phi * v[j];
      ++used;
    }
    if (used < 4) continue;
    const Eigen::Vector3d c = A.ldlt().solve(y);
    smoothed[k] = c[0];
    slope[k] = c[1] / scale;
  }
}

DiagnosisReport diagnose(const lang::Model& model, const DiagnosisOptions& options) {
  detail::Engine e(model, options);
  return e.run();
}

} // namespace thermnet
