#pragma once
/// A requirement of the model (`require ...`) elaborated for one case: its members resolved to
/// nodes or elements, its limits in SI.

#include "lang/source.hpp"

#include <limits>
#include <string>
#include <vector>

namespace thermnet::lang {

/// What a requirement limits.
enum class RequirementKind {
  band,     ///< every member node stays within [lo, hi], K
  gradient, ///< max |T_i - T_j| over the members (of one group, or between two groups) <= hi, K
  power,    ///< peak of the summed power of the member elements <= hi, W
  energy,   ///< energy of the member elements <= hi, J
  margin    ///< the members' installed power >= (1 + lo) x the mean power they deliver
};

/// The keyword of a requirement kind ("band", ...).
const char* requirement_keyword(RequirementKind k);

/// How a requirement's values are shown: the unit the model wrote its limit in.
struct DisplayUnit {
  std::string text;    ///< unit text ("degC", "K", "W", "kJ", "%")
  double scale = 1.0;  ///< SI = scale * shown + offset
  double offset = 0.0; ///< (non-zero for degC/degF on absolute temperatures)
  /// An SI value in this unit.
  double shown(double si) const { return (si - offset) / scale; }
  /// A difference in SI in this unit.
  double shown_difference(double si) const { return si / scale; }
};

/// One requirement for one case.
struct RequirementSpec {
  RequirementKind kind = RequirementKind::band;         ///< what it limits
  std::vector<std::string> groups;                      ///< the name patterns as written
  std::vector<int> members;                             ///< nodes (band, gradient) or elements
  std::vector<int> others;                              ///< gradient: the second group's nodes
  double lo = -std::numeric_limits<double>::infinity(); ///< lower limit (band, margin), SI
  double hi = std::numeric_limits<double>::infinity();  ///< upper limit (others), SI
  double from = 0.0;                                    ///< checked from this time on, s
  DisplayUnit unit;                                     ///< unit of reports
  std::string text;                                     ///< the statement as written
  std::string doc;                                      ///< description
  Span where;                                           ///< the statement
};

} // namespace thermnet::lang
