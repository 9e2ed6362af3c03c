#pragma once
/// Requirement outcomes as text lines and JSON (check, simulate, design).

#include "kernel/core/requirement_check.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace thermnet::app {

/// One JSON object per outcome: file, line, column, kind, requirement, case, met, worst, slack
/// (in `unit`), time, where, and duty for a margin.
nlohmann::json outcomes_json(const std::vector<RequirementOutcome>& outcomes,
                             const lang::SourceManager& sources);

/// The outcome lines (format_outcome), one per line.
std::string outcomes_text(const std::vector<RequirementOutcome>& outcomes,
                          const lang::SourceManager& sources);

/// The number of violated outcomes.
std::size_t violations(const std::vector<RequirementOutcome>& outcomes);

} // namespace thermnet::app
