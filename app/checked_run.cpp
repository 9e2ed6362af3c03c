#include "app/checked_run.hpp"

#include "app/result_output.hpp"

#include <algorithm>

namespace thermnet::app {

bool CheckedRun::met() const {
  return std::all_of(outcomes.begin(), outcomes.end(),
                     [](const RequirementOutcome& o) { return o.met; });
}

CheckedRun run_checked(const lang::Model& model, const std::string& case_name,
                       const lang::ParamValues& params, const SimulationOptions& options,
                       const std::vector<std::string>& keep) {
  CheckedRun run;
  run.net = std::make_unique<Network>(params.empty() ? model.take_network(case_name)
                                                     : model.instantiate(case_name, params));
  Network& net = *run.net;
  const lang::NetworkSpec& spec = net.spec();
  RequirementCheck check(spec);
  std::vector<std::size_t> columns;
  if (!keep.empty()) {
    std::vector<std::string> names;
    for (const auto& n : spec.nodes)
      names.push_back(n.name);
    columns = plot_columns(names, keep);
    for (std::size_t c : columns)
      run.kept.names.push_back(names[c]);
  }
  std::vector<std::vector<double>> heat;
  std::vector<double> unknowns(static_cast<std::size_t>(net.size()));
  const auto row = [&](double t, const std::vector<double>& temps) {
    if (check.needs_heat()) {
      for (std::size_t u = 0; u < unknowns.size(); ++u)
        unknowns[u] = temps[static_cast<std::size_t>(net.unknown_nodes()[u])];
      net.element_heat(t, unknowns.data(), heat);
    }
    check.add(t, temps, heat);
    if (columns.empty()) return;
    run.kept.times.push_back(t);
    std::vector<double> r;
    for (std::size_t c : columns)
      r.push_back(temps[c]);
    run.kept.temps.push_back(std::move(r));
  };
  run.kept.stats = simulate(net, options, row, options.steady ? nullptr : &run.energy);
  run.outcomes = check.outcomes();
  return run;
}

} // namespace thermnet::app
