#include "app/requirement_report.hpp"

#include <algorithm>
#include <cmath>

namespace thermnet::app {

namespace {
/// A JSON number, or null when not finite (an unbounded margin, a run too short).
nlohmann::json json_number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}
} // namespace

nlohmann::json outcomes_json(const std::vector<RequirementOutcome>& outcomes,
                             const lang::SourceManager& sources) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& o : outcomes) {
    const OutcomeFields f = outcome_fields(o, sources);
    nlohmann::json j{{"file", f.file},
                     {"line", f.line},
                     {"column", f.column},
                     {"kind", f.kind},
                     {"requirement", f.text},
                     {"case", o.case_name},
                     {"met", o.met},
                     {"unit", f.unit},
                     {"worst", json_number(f.worst)},
                     {"slack", json_number(f.slack)},
                     {"time", o.time},
                     {"where", o.where}};
    if (o.req->kind == lang::RequirementKind::margin) j["duty"] = o.duty;
    out.push_back(std::move(j));
  }
  return out;
}

std::string outcomes_text(const std::vector<RequirementOutcome>& outcomes,
                          const lang::SourceManager& sources) {
  std::string s;
  for (const auto& o : outcomes)
    s += format_outcome(o, sources) + "\n";
  return s;
}

std::size_t violations(const std::vector<RequirementOutcome>& outcomes) {
  return static_cast<std::size_t>(
      std::count_if(outcomes.begin(), outcomes.end(), [](const auto& o) { return !o.met; }));
}

} // namespace thermnet::app
