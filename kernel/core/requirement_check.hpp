#pragma once
/// Checking a run of a case against the model's requirements (`require ...`), row by row at the
/// output times: bands and gradients on the sampled temperatures, power, energy and margin on the
/// sampled heat of the member sources (energy by the trapezoidal rule over the rows).

#include "lang/network_spec.hpp"

#include <string>
#include <vector>

namespace thermnet {

/// What one run shows for one requirement.
struct RequirementOutcome {
  const lang::RequirementSpec* req = nullptr; ///< the requirement (owned by the NetworkSpec)
  std::string case_name;                      ///< the case run
  bool met = true;                            ///< slack >= 0
  double slack = 0.0; ///< distance to the limit at the worst point, SI (< 0: violated by -slack)
  double worst = 0.0; ///< the value at the worst point (temperature, spread, W, J, margin), SI
  double time = 0.0;  ///< when the worst point occurred, s (energy, margin: the end)
  std::string where;  ///< the node, node pair or element at the worst point ("" for a sum)
  double duty = 0.0;  ///< margin: the members' mean delivered power / installed power
};

/// Accumulates the requirements of one case over the output rows of its run.
class RequirementCheck {
public:
  /// Checks `spec.requirements` (the spec must outlive the check).
  explicit RequirementCheck(const lang::NetworkSpec& spec);
  /// True when some requirement needs the sources' heat in add().
  bool needs_heat() const { return needs_heat_; }
  /// Adds one output row: time, every node's temperature (K, spec order) and, when needs_heat(),
  /// every element's heat into its terminals (Network::element_heat).
  void add(double t, const std::vector<double>& temps,
           const std::vector<std::vector<double>>& heat);
  /// The outcome of each requirement, in the spec's order.
  std::vector<RequirementOutcome> outcomes() const;

private:
  struct State {
    double slack = 0.0, worst = 0.0, time = 0.0;
    std::string where;
    bool seen = false;
    double energy = 0.0, last_power = 0.0, last_t = 0.0, first_t = 0.0;
    std::vector<double> member_energy, member_last;
  };
  void update(State& s, double slack, double worst, double t, const std::string& where) const;

  const lang::NetworkSpec& spec_;
  std::vector<State> states_;
  bool needs_heat_ = false;
};

/// One line per outcome: "FILE:LINE:COL: requirement met|VIOLATED: TEXT [case C]: ...", in the
/// requirement's units.
std::string format_outcome(const RequirementOutcome& o, const lang::SourceManager& sources);

/// The outcome as JSON-ready fields (used by check and design): met, slack, worst, time, where,
/// in the requirement's display unit, plus the statement, file, line and column.
struct OutcomeFields {
  std::string file;    ///< file of the statement
  unsigned line = 0;   ///< its line
  unsigned column = 0; ///< its column
  std::string kind;    ///< band, gradient, ...
  std::string text;    ///< the statement
  std::string unit;    ///< display unit
  double slack = 0.0;  ///< slack in the display unit (difference)
  double worst = 0.0;  ///< worst value in the display unit
};
/// The fields of an outcome in its display unit.
OutcomeFields outcome_fields(const RequirementOutcome& o, const lang::SourceManager& sources);

} // namespace thermnet
