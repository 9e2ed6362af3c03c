#pragma once
/// The energy balance of a transient (per node, per boundary, per source, in total) and the duty of
/// each thermostat, as text.

#include "kernel/core/energy_account.hpp"
#include "lang/network_spec.hpp"

#include <string>

namespace thermnet::app {

/// Totals over the whole network, J.
struct EnergyBalance {
  double stored = 0.0;   ///< sum over nodes of C (T_end - T_start)
  double supplied = 0.0; ///< heat put in by one-terminal elements (heaters, thermostats)
  double lost = 0.0;     ///< heat received by the boundaries
  /// stored - (supplied - lost): the integration error (and any element that does not conserve
  /// heat, such as a Peltier cooler's electric power).
  double residual() const { return stored - (supplied - lost); }
};

/// Sums the totals of a run.
EnergyBalance energy_balance(const lang::NetworkSpec& spec, const EnergyTotals& totals);

/// The report: per node stored energy, heat from sources and through links, residual; per
/// boundary the heat received; per thermostat its on time, duty cycle, switch count and energy;
/// then the totals.
std::string energy_report(const lang::NetworkSpec& spec, const EnergyTotals& totals);

} // namespace thermnet::app
