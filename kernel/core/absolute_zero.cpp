// Temperatures below absolute zero: an unphysical state reported with its node, time and causes.

#include "kernel/core/absolute_zero.hpp"

#include "kernel/core/solver_types.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>

#include <string>

namespace thermnet::detail {

namespace {

/// 0 degC in kelvin.
using lang::kZeroCelsius;

} // namespace

int coldest_below_absolute_zero(const double* T, int n) {
  int coldest = -1;
  for (int i = 0; i < n; ++i)
    if (T[i] < 0.0 && (coldest < 0 || T[i] < T[coldest])) coldest = i;
  return coldest;
}

void fail_below_absolute_zero(const SystemEvaluator& ev, const BelowAbsoluteZero& b,
                              const char* call) {
  const std::string node = ev.name(b.unknown);
  const bool massless = ev.capacities()[static_cast<std::size_t>(b.unknown)] == 0.0;
  const std::string where =
      b.steady ? fmt::format("in the steady state of the inputs at t = {:.10g} s ({:.6g} K = "
                             "{:.6g} degC)",
                             b.crossing, b.kelvin, b.kelvin - kZeroCelsius)
               : fmt::format("at t = {:.10g} s (it reaches {:.6g} K = {:.6g} degC at t = {:.10g} "
                             "s)",
                             b.crossing, b.kelvin, b.kelvin - kZeroCelsius, b.reached);
  std::string hint = "more heat is drawn from it than its links can bring (a negative heater "
                     "power or heat flow?)";
  if (massless)
    hint += "; on a node without heat capacity, radiation (T^4) may also balance the heat at its "
            "unphysical negative root";
  throw SolverError(
      fmt::format("the temperature of node {} falls below absolute zero {}: {}", node, where, hint),
      call, 0, b.crossing, {node});
}

} // namespace thermnet::detail
