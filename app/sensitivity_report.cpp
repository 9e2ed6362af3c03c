// The sensitivity report as JSON.

#include "app/sensitivity_report.hpp"

#include "lang/units.hpp"

#include <cmath>

namespace thermnet::app {

nlohmann::json sensitivity_json(const lang::Model& model, const SensitivityReport& r) {
  nlohmann::json factors = nlohmann::json::array();
  for (std::size_t j = 0; j < r.factors.size(); ++j) {
    const SensitivityFactor& f = r.factors[j];
    nlohmann::json s = nlohmann::json::object();
    for (std::size_t i = 0; i < r.outputs.size(); ++i)
      s[r.outputs[i]] = r.matrix[j][i];
    nlohmann::json e = {{"name", f.name},
                        {"kind", f.kind},
                        {"scale", f.scale},
                        {"total", r.total[j]},
                        {"sensitivities", s}};
    e["value"] = std::isnan(f.value) ? nlohmann::json(nullptr)
                 : f.temperature     ? nlohmann::json(f.value - lang::kZeroCelsius)
                                     : nlohmann::json(f.value);
    if (f.temperature) e["unit"] = "degC";
    if (f.lo) e["lo"] = *f.lo;
    if (f.hi) e["hi"] = *f.hi;
    factors.push_back(e);
  }
  nlohmann::json ranking = nlohmann::json::array();
  for (std::size_t j : r.ranking)
    ranking.push_back(r.factors[j].name);
  return {{"model", model.name()},
          {"definition", "S = RMS over time of dT/dp * (hi - lo) for ranged params, * |p| "
                         "otherwise (central differences, 1 % steps), K"},
          {"cases", r.cases},
          {"outputs", r.outputs},
          {"factors", factors},
          {"matrix", r.matrix},
          {"ranking", ranking},
          {"simulations", r.simulations},
          {"notes", r.notes}};
}

} // namespace thermnet::app
