#pragma once
/// The model statements of a measurement-side finding (a sensor's lag or offset): a `sensor` of
/// the node, or, when the model already reads the node through a sensor, that sensor's key set in
/// every case, so that the extended model diagnosed again continues from the finding.

#include "kernel/diagnosis/hypothesis.hpp"

#include <string>

namespace thermnet {

/// The sensor of the declared model that reads node `node` alone, or "" when there is none.
std::string sensor_of_node(const Evidence& ev, const std::string& node);

/// `sensor NAME NODE KEY = VALUE [UNIT]` for a node without a sensor; a comment naming the
/// model's own sensor otherwise (its key is then set in the case blocks: sensor_case_lines()).
std::string sensor_statement(const Evidence& ev, const std::string& kind, const std::string& node,
                             const std::string& key, double value, const std::string& unit);

/// `SENSOR.KEY = VALUE [UNIT]` in every declared case when the model reads node `node` through a
/// sensor of its own (nothing otherwise).
CaseLines sensor_case_lines(const Evidence& ev, const std::string& node, const std::string& key,
                            double value, const std::string& unit);

} // namespace thermnet
