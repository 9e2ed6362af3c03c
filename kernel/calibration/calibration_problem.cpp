// CalibrationProblem: simulate every case at a point, compare with the data at the measured times
// (dense output of the integrator), abandon early at the first residual over the tolerance.

#include "kernel/calibration/calibration_problem.hpp"

#include "kernel/core/integrator.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace thermnet {

namespace {

/// Thrown from the output callback to stop a simulation at the first residual over the
/// tolerance; never leaves evaluate(). The integrator's SUNDIALS memory is owned by RAII, so
/// unwinding through integrate() frees it.
struct Abandon {};

/// Simulates one case from t = 0 to its last measured time and calls visit(k, sim) at each
/// measured time k with the simulated value of every measured series (K, series order).
template <class Visit>
void run_case(lang::NetworkSpec spec, const MeasuredData& data, const SolverOptions& solver,
              Visit&& visit) {
  if (data.times.empty()) return;
  Network net(std::move(spec));
  std::vector<double> T = start_state(net, solver);
  std::vector<double> all(net.spec().nodes.size()), sim(data.series.size());
  std::size_t k = 0;
  integrate(
      net, T, 0.0, data.times.back(), data.times,
      [&](double t, const std::vector<double>& x) {
        net.expand(t, x.data(), all.data());
        for (std::size_t s = 0; s < sim.size(); ++s)
          sim[s] = simulated_value(net, data.series[s], t, x.data(), all.data());
        visit(k++, sim);
      },
      solver);
  if (k != data.times.size())
    throw std::runtime_error(
        fmt::format("the simulation gave {} of the {} measured times", k, data.times.size()));
}

} // namespace

CalibrationProblem::CalibrationProblem(const lang::Model& model, std::vector<std::string> cases)
    : model_(&model) {
  for (auto& p : model.params())
    if (p.ranged()) params_.push_back(std::move(p));
  const bool all = cases.empty();
  if (all) cases = model.run_case_names();
  for (const auto& requested : cases) {
    std::string name = model.resolve_case(requested);
    if (std::find(cases_.begin(), cases_.end(), name) != cases_.end()) continue; // listed twice
    lang::NetworkSpec spec = model.instantiate(name);
    if (spec.settings.data_path.empty()) {
      if (all) continue;
      throw std::invalid_argument(fmt::format("case '{}' has no data file", name));
    }
    data_.push_back(load_measured(spec.settings.data_path, spec));
    cases_.push_back(name);
  }
  // R^2 denominator: the spread of every measured point around their common mean, summed about
  // the first point (constant data give exactly 0, not the round-off of a mean: R^2 -2e23).
  double first = std::numeric_limits<double>::quiet_NaN(), sum = 0.0;
  std::size_t n = 0;
  for (const auto& d : data_)
    for (const auto& s : d.series)
      for (double v : s.values)
        if (!std::isnan(v)) {
          if (n == 0) first = v;
          sum += v - first, ++n;
        }
  const double mean = n > 0 ? sum / static_cast<double>(n) : 0.0; // about `first`
  for (const auto& d : data_)
    for (const auto& s : d.series)
      for (double v : s.values)
        if (!std::isnan(v)) sst_ += (v - first - mean) * (v - first - mean);
}

double CalibrationProblem::r_squared(double sse) const {
  return sst_ > 0.0 ? 1.0 - sse / sst_ : std::numeric_limits<double>::quiet_NaN();
}

std::vector<double> CalibrationProblem::lower() const {
  std::vector<double> v;
  for (const auto& p : params_)
    v.push_back(*p.lo);
  return v;
}

std::vector<double> CalibrationProblem::upper() const {
  std::vector<double> v;
  for (const auto& p : params_)
    v.push_back(*p.hi);
  return v;
}

std::vector<double> CalibrationProblem::initial() const {
  std::vector<double> v;
  for (const auto& p : params_)
    v.push_back(p.value);
  return v;
}

std::size_t CalibrationProblem::points() const {
  std::size_t n = 0;
  for (const auto& d : data_)
    n += d.points();
  return n;
}

lang::ParamValues CalibrationProblem::values(const std::vector<double>& x) const {
  if (x.size() != params_.size())
    throw std::invalid_argument(
        fmt::format("a point has {} values for {} ranged params", x.size(), params_.size()));
  lang::ParamValues v;
  for (std::size_t j = 0; j < x.size(); ++j)
    v.emplace(params_[j].name, x[j]);
  return v;
}

Evaluation CalibrationProblem::evaluate(const std::vector<double>& x,
                                        const EvaluationOptions& opt) const {
  Evaluation ev;
  const double limit = opt.tolerance.value_or(std::numeric_limits<double>::infinity());
  std::vector<double> residuals;
  if (opt.keep_residuals) residuals.reserve(points());
  try {
    for (double v : x)
      if (!std::isfinite(v)) throw std::invalid_argument("a param value is not finite");
    const lang::ParamValues pv = values(x);
    for (std::size_t c = 0; c < cases_.size(); ++c) {
      const MeasuredData& data = data_[c];
      ++ev.simulations;
      run_case(model_->instantiate(cases_[c], pv), data, opt.solver,
               [&](std::size_t k, const std::vector<double>& sim) {
                 for (std::size_t s = 0; s < sim.size(); ++s) {
                   const double m = data.series[s].values[k];
                   if (std::isnan(m)) continue;
                   const double r = sim[s] - m;
                   ev.sse += r * r;
                   ++ev.points;
                   if (opt.keep_residuals) residuals.push_back(r);
                   // The study keeps a sample only if every |T_calc - T_meas| < T_lim.
                   if (!(std::abs(r) < limit)) throw Abandon{};
                 }
               });
    }
    ev.ok = true;
    ev.accepted = true;
  } catch (const Abandon&) {
    ev.ok = true;
    ev.abandoned = true;
  } catch (const std::exception& e) {
    ev.failure = e.what();
  }
  ev.rmse = ev.points > 0 ? std::sqrt(ev.sse / static_cast<double>(ev.points)) : 0.0;
  ev.r2 = r_squared(ev.sse);
  if (ev.accepted && opt.keep_residuals) ev.residuals = std::move(residuals);
  return ev;
}

std::vector<CalibrationProblem::CaseComparison>
CalibrationProblem::compare(const std::vector<double>& x, const SolverOptions& solver) const {
  const lang::ParamValues pv = values(x);
  std::vector<CaseComparison> out;
  for (std::size_t c = 0; c < cases_.size(); ++c) {
    CaseComparison cc;
    cc.case_name = cases_[c];
    cc.measured = data_[c];
    cc.simulated.assign(cc.measured.series.size(), {});
    run_case(model_->instantiate(cases_[c], pv), cc.measured, solver,
             [&](std::size_t, const std::vector<double>& sim) {
               for (std::size_t s = 0; s < sim.size(); ++s)
                 cc.simulated[s].push_back(sim[s]);
             });
    out.push_back(std::move(cc));
  }
  return out;
}

} // namespace thermnet
