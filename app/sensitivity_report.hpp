#pragma once
/// The sensitivity report as JSON (`thermnet sensitivity --json`, the Python module's
/// sensitivity()).

#include "kernel/calibration/sensitivity.hpp"
#include "lang/model.hpp"

#include <nlohmann/json.hpp>

namespace thermnet::app {

/// The --json report: model, definition, cases, outputs, factors, matrix, ranking, simulations,
/// notes.
nlohmann::json sensitivity_json(const lang::Model& model, const SensitivityReport& r);

} // namespace thermnet::app
