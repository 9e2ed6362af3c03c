// Normalised sensitivities by central differences over whole simulations (see sensitivity.hpp).
// Every (factor, case) pair is one task of parallel_for writing its own slot; the reduction
// runs serially in index order, so the report does not depend on the number of threads.

#include "kernel/calibration/sensitivity.hpp"

#include "kernel/core/measured_data.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/parallel.hpp"
#include "kernel/core/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_map>

namespace thermnet {
namespace {

constexpr double kTightTolerance = 1e-9;

/// A compared case: its nominal spec and run, and which nodes it outputs.
struct CaseRun {
  std::string name;
  lang::NetworkSpec spec;
  std::vector<int> nodes;         // spec node index of each output of this case
  std::vector<std::size_t> slots; // report output index of each
  SimulationResult nominal;
};

/// Where an element key lives in a spec: element index, part index (-1: the element), key.
struct KeyRef {
  std::size_t element = 0;
  int part = -1;
  std::string key;
};

/// Builds a perturbed spec of a case for a sign (+1/-1); throws if the value is invalid.
using Perturb = std::function<lang::NetworkSpec(const CaseRun&, double sign)>;

lang::ElementSpec& element_at(lang::NetworkSpec& spec, const KeyRef& ref) {
  lang::ElementSpec& e = spec.elements.at(ref.element);
  return ref.part < 0 ? e : e.edit_parts().at(static_cast<std::size_t>(ref.part));
}

bool nonzero(const lang::Signal& s) {
  if (s.is_constant()) return s.constant != 0.0;
  return std::any_of(s.values().begin(), s.values().end(), [](double v) { return v != 0.0; });
}

/// Adds the numeric keys of one element (or composite part) as factors.
void add_element_keys(const lang::ElementSpec& e, const std::string& label, std::size_t index,
                      int part, double rel, std::vector<SensitivityFactor>& factors,
                      std::vector<Perturb>& perturbs) {
  for (const auto& [key, signal] : e.values) {
    if (!nonzero(signal)) continue;
    SensitivityFactor f;
    f.name = fmt::format("{}.{}", label, key);
    f.kind = "element";
    f.value = signal.is_constant() ? signal.constant : std::numeric_limits<double>::quiet_NaN();
    f.scale = signal.is_constant() ? std::abs(signal.constant) : 1.0;
    const lang::KeySchema* schema = e.schema ? e.schema->key(key) : nullptr;
    f.temperature = schema && schema->absolute_temperature;
    if (f.temperature) f.scale = 1.0; // per kelvin of change
    factors.push_back(f);
    KeyRef ref{index, part, std::string(key)};
    perturbs.push_back([ref, rel, shift = f.temperature](const CaseRun& c, double sign) {
      lang::NetworkSpec spec = c.spec;
      lang::Signal& s = element_at(spec, ref).values.at(ref.key);
      if (!shift) {
        s = s.scaled(1.0 + sign * rel);
        return spec;
      }
      s.constant += sign * rel; // rel K: S = (T+ - T-) / (2 rel) is then per kelvin
      if (s.shape_if())
        for (double& v : s.shape().v)
          v += sign * rel;
      return spec;
    });
  }
}

/// Element keys and node capacities of a spec, as factors perturbed relative to their value.
void add_element_factors(const lang::NetworkSpec& spec, double rel,
                         std::vector<SensitivityFactor>& factors, std::vector<Perturb>& perturbs) {
  for (std::size_t i = 0; i < spec.elements.size(); ++i) {
    const lang::ElementSpec& e = spec.elements[i];
    if (e.composite() == lang::Composite::none) {
      add_element_keys(e, e.name, i, -1, rel, factors, perturbs);
      continue;
    }
    std::map<std::string, int> seen;
    for (const auto& part : e.parts())
      ++seen[std::string(part.kind())];
    std::map<std::string, int> count;
    for (std::size_t k = 0; k < e.parts().size(); ++k) {
      const std::string kind(e.parts()[k].kind());
      std::string label = e.name + "." + kind;
      if (seen[kind] > 1) label += fmt::format("#{}", ++count[kind]);
      add_element_keys(e.parts()[k], label, i, static_cast<int>(k), rel, factors, perturbs);
    }
  }
  for (std::size_t i = 0; i < spec.nodes.size(); ++i) {
    const lang::NodeSpec& n = spec.nodes[i];
    if (n.boundary || n.C == 0.0) continue;
    SensitivityFactor f;
    f.name = n.name + ".C";
    f.kind = "element";
    f.value = n.C;
    f.scale = std::abs(n.C);
    factors.push_back(f);
    perturbs.push_back([i, rel](const CaseRun& c, double sign) {
      lang::NetworkSpec spec = c.spec;
      spec.nodes[i].C *= 1.0 + sign * rel;
      return spec;
    });
  }
}

std::vector<std::string> compared_cases(const lang::Model& model, const SensitivityOptions& o) {
  std::vector<std::string> cases;
  for (const std::string& name : o.cases)
    cases.push_back(model.resolve_case(name));
  if (!cases.empty()) return cases;
  for (const std::string& name : model.case_names())
    if (!model.instantiate(name).settings.data_path.empty()) cases.push_back(name);
  if (!cases.empty()) return cases;
  return model.run_case_names();
}

/// Per task: sum of squared scaled differences per case output, and the sides that failed.
struct TaskResult {
  std::vector<double> sum_sq;
  bool plus_failed = false;
  bool minus_failed = false;
};

} // namespace

SensitivityReport compute_sensitivities(const lang::Model& model, const SensitivityOptions& o) {
  SensitivityReport rep;
  SimulationOptions sim;
  sim.solver = o.solver;
  sim.solver.rtol = std::min(o.solver.rtol, kTightTolerance);
  sim.solver.atol = std::min(o.solver.atol, kTightTolerance);

  // Cases, their outputs and nominal runs.
  rep.cases = compared_cases(model, o);
  std::vector<CaseRun> runs;
  bool any_data = false;
  for (const std::string& name : rep.cases) {
    CaseRun c;
    c.name = name;
    c.spec = model.instantiate(name);
    if (!c.spec.settings.data_path.empty()) {
      any_data = true;
      for (const MeasuredSeries& s : load_measured(c.spec.settings.data_path, c.spec).series)
        if (!c.spec.nodes[static_cast<std::size_t>(s.node_index)].boundary)
          c.nodes.push_back(s.node_index);
    }
    runs.push_back(std::move(c));
  }
  std::unordered_map<std::string, std::size_t> output_slot; // rep.outputs by name
  for (CaseRun& c : runs) {
    if (!any_data)
      for (std::size_t i = 0; i < c.spec.nodes.size(); ++i)
        if (!c.spec.nodes[i].boundary) c.nodes.push_back(static_cast<int>(i));
    for (int node : c.nodes) {
      const std::string& n = c.spec.nodes[static_cast<std::size_t>(node)].name;
      const auto [it, added] = output_slot.try_emplace(n, rep.outputs.size());
      c.slots.push_back(it->second);
      if (added) rep.outputs.push_back(n);
    }
  }
  std::vector<std::string> failures(runs.size());
  parallel_for(runs.size(), o.threads, [&](std::size_t k) {
    try {
      Network net(runs[k].spec);
      runs[k].nominal = simulate(net, sim);
    } catch (const std::exception& e) {
      failures[k] = e.what();
    }
  });
  rep.simulations += runs.size();
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (!failures[k].empty())
      throw SolverError("nominal run of case '" + runs[k].name + "' failed: " + failures[k],
                        "simulate", 0, 0.0, {});

  // Factors: every param (ranged: over its range; fixed: relative), then element keys.
  std::vector<Perturb> perturbs;
  for (const lang::ParamInfo& p : model.params()) {
    SensitivityFactor f;
    f.name = p.name;
    f.kind = "param";
    f.value = p.value;
    f.lo = p.lo;
    f.hi = p.hi;
    f.scale = p.ranged() ? *p.hi - *p.lo : std::abs(p.value);
    if (f.scale == 0.0) {
      rep.notes.push_back("param '" + p.name + "' is zero and has no range: skipped");
      continue;
    }
    const double d = o.relative_step * f.scale;
    rep.factors.push_back(f);
    perturbs.push_back([&model, name = p.name, value = p.value, d](const CaseRun& c, double sign) {
      return model.instantiate(c.name, lang::ParamValues{{name, value + sign * d}});
    });
  }
  if (o.elements) add_element_factors(runs.front().spec, o.relative_step, rep.factors, perturbs);

  // One task per (factor, case): both sides, reduced to sums of squares per case output.
  const std::size_t nf = rep.factors.size(), nc = runs.size();
  std::vector<TaskResult> tasks(nf * nc);
  parallel_for(
      tasks.size(), o.threads,
      [&](std::size_t t) {
        const std::size_t j = t / nc;
        const CaseRun& c = runs[t % nc];
        TaskResult& out = tasks[t];
        auto side = [&](double sign, bool& failed) -> SimulationResult {
          try {
            Network net(perturbs[j](c, sign));
            return simulate(net, sim);
          } catch (const std::exception&) {
            failed = true;
            return c.nominal;
          }
        };
        SimulationResult plus = side(+1.0, out.plus_failed);
        SimulationResult minus = side(-1.0, out.minus_failed);
        out.sum_sq.assign(c.nodes.size(), 0.0);
        if (out.plus_failed && out.minus_failed) return;
        // S = (T+ - T-) / (2 d) * scale = (T+ - T-) / (2 rel) for both kinds of factor.
        const double span = (out.plus_failed || out.minus_failed ? 1.0 : 2.0) * o.relative_step;
        const std::size_t times = std::min(plus.times.size(), minus.times.size());
        for (std::size_t k = 0; k < c.nodes.size(); ++k) {
          const auto node = static_cast<std::size_t>(c.nodes[k]);
          for (std::size_t m = 0; m < times; ++m) {
            const double s = (plus.temps[m][node] - minus.temps[m][node]) / span;
            out.sum_sq[k] += s * s;
          }
        }
      },
      o.cancel);

  // Serial reduction: RMS pooled over the cases' output times.
  rep.matrix.assign(nf, std::vector<double>(rep.outputs.size(), 0.0));
  std::vector<double> counts(rep.outputs.size(), 0.0);
  for (const CaseRun& c : runs)
    for (std::size_t slot : c.slots)
      counts[slot] += static_cast<double>(c.nominal.times.size());
  for (std::size_t j = 0; j < nf; ++j) {
    for (std::size_t ci = 0; ci < nc; ++ci) {
      const TaskResult& t = tasks[j * nc + ci];
      rep.simulations += 2;
      if (t.plus_failed || t.minus_failed)
        rep.notes.push_back(fmt::format(
            "{} '{}' in case '{}': {}", rep.factors[j].kind, rep.factors[j].name, runs[ci].name,
            t.plus_failed && t.minus_failed ? "both perturbed runs failed: sensitivity set to 0"
                                            : "one perturbed run failed: one-sided difference"));
      for (std::size_t k = 0; k < t.sum_sq.size(); ++k)
        rep.matrix[j][runs[ci].slots[k]] += t.sum_sq[k];
    }
    for (std::size_t i = 0; i < rep.outputs.size(); ++i)
      rep.matrix[j][i] = counts[i] > 0 ? std::sqrt(rep.matrix[j][i] / counts[i]) : 0.0;
  }
  for (const auto& row : rep.matrix)
    rep.total.push_back(std::accumulate(row.begin(), row.end(), 0.0));
  rep.ranking.resize(nf);
  std::iota(rep.ranking.begin(), rep.ranking.end(), std::size_t{0});
  std::stable_sort(rep.ranking.begin(), rep.ranking.end(),
                   [&](std::size_t a, std::size_t b) { return rep.total[a] > rep.total[b]; });
  return rep;
}

} // namespace thermnet
