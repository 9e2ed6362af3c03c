#include "kernel/estimation/estimator.hpp"

#include "lang/name_list.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <charconv>
#include <cmath>

namespace thermnet {

std::string EstimatorSettings::text(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

double EstimatorSettings::number(const std::string& name, double fallback) const {
  auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  const std::string& s = it->second;
  double v = 0.0;
  const char* b = s.data() + (!s.empty() && s[0] == '+' ? 1 : 0);
  auto [p, ec] = std::from_chars(b, s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v))
    throw EstimatorError(fmt::format("option '{}' must be a number, got '{}'", name, s));
  return v;
}

std::vector<std::string> EstimatorSettings::list(const std::string& name) const {
  std::vector<std::string> pieces{{}};
  for (char c : text(name)) {
    if (c == ',')
      pieces.emplace_back();
    else if (c != ' ')
      pieces.back() += c;
  }
  // A generated name holds commas inside its brackets (`p[1,2]`): its pieces are joined again.
  std::vector<std::string> out;
  for (auto& item : lang::join_bracketed(pieces))
    if (!item.empty()) out.push_back(std::move(item));
  return out;
}

bool EstimatorSettings::flag(const std::string& name) const {
  std::string s = text(name);
  return s == "1" || s == "true" || s == "yes";
}

int require_column(const std::vector<std::string>& columns, const std::string& name,
                   const std::string& what) {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  throw EstimatorError(fmt::format("{} '{}' is not a column of the data (columns: {})", what, name,
                                   fmt::join(columns, ", ")));
}

} // namespace thermnet
