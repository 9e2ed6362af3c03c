#pragma once
/// Normalised sensitivities of node temperature histories to params and element values.
///
/// For a factor p_j (a param, or with `elements` a numeric key of an element or a node's
/// capacity) and an output node i:
///
///   S_ij = RMS over the output times of every compared case of
///          [T_i(p_j + d) - T_i(p_j - d)] / (2 d) * scale_j          (kelvin)
///
/// with scale_j = hi - lo for a ranged param (the linearised effect of sweeping the param over
/// its range, as in the study's ranking) and scale_j = |p_j| otherwise (the effect of a 100 %
/// change: p dT/dp). The step d is 1 % of scale_j; a side that cannot be simulated (a value out
/// of its valid range) is replaced by the nominal run (one-sided difference). Simulations use
/// rtol = atol = 1e-9 so the integration noise stays far below the step effect.
///
/// Outputs are the measured nodes of every compared case (the cases with data; RMS pooled over
/// cases), or every non-boundary node when no compared case has data.

#include "kernel/core/integrator.hpp"
#include "lang/model.hpp"

#include <atomic>
#include <optional>
#include <string>
#include <vector>

namespace thermnet {

/// What to compute.
struct SensitivityOptions {
  bool elements = false;          ///< also every numeric element key and node capacity
  std::vector<std::string> cases; ///< cases to compare (empty: those with data, else the default)
  int threads = 0;                ///< worker threads (0: all cores); results do not depend on it
  double relative_step = 0.01;    ///< d as a fraction of scale_j
  SolverOptions solver;           ///< simulation settings (rtol/atol capped at 1e-9)
  const std::atomic<bool>* cancel = nullptr; ///< set to stop early
};

/// One perturbed quantity.
struct SensitivityFactor {
  std::string name;         ///< param name, "element.key" or "node.C"
  std::string kind;         ///< "param" or "element"
  double value = 0.0;       ///< nominal value, SI (NaN for a time-dependent signal)
  std::optional<double> lo; ///< range low end (ranged params)
  std::optional<double> hi; ///< range high end
  double scale = 0.0;       ///< hi - lo, or |value| (1 for a signal scaled by a factor)
  /// A temperature key (a thermostat's on/off): value in K, perturbed by +-relative_step K and
  /// scaled per kelvin (scale 1 K), since its size in K says nothing about its effect.
  bool temperature = false;
};

/// The matrix and the ranking.
struct SensitivityReport {
  std::vector<std::string> cases;          ///< compared cases
  std::vector<std::string> outputs;        ///< output node names
  std::vector<SensitivityFactor> factors;  ///< factors, in declaration order
  std::vector<std::vector<double>> matrix; ///< matrix[j][i]: S of factor j on output i, K
  std::vector<double> total;               ///< per factor: sum over outputs of S, K
  std::vector<std::size_t> ranking;        ///< factor indices by decreasing total (stable)
  std::vector<std::string> notes;          ///< one-sided differences, failures
  std::size_t simulations = 0;             ///< case simulations run
};

/// Computes the sensitivities of a model; throws lang::ModelError for a bad case or model,
/// lang::CsvError for bad data, SolverError if a nominal run fails.
SensitivityReport compute_sensitivities(const lang::Model& model,
                                        const SensitivityOptions& options = {});

} // namespace thermnet
