#include "app/node_summary.hpp"

#include "app/csv_writer.hpp"
#include "lang/units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

namespace thermnet::app {

namespace {
using lang::kZeroCelsius;

/// Time within [t0, t1] that a linear segment from a to b spends outside [lo, hi].
double outside_time(double t0, double t1, double a, double b, double lo, double hi) {
  const double dt = t1 - t0;
  if (dt <= 0.0) return 0.0;
  // Fraction of the segment below lo plus fraction above hi (linear in between).
  const auto fraction_beyond = [](double x0, double x1, double limit) { // part with x > limit
    if (x0 <= limit && x1 <= limit) return 0.0;
    if (x0 > limit && x1 > limit) return 1.0;
    const double f = (x0 > limit ? x0 - limit : x1 - limit) / std::abs(x1 - x0);
    return f;
  };
  return dt * (fraction_beyond(-a, -b, -lo) + fraction_beyond(a, b, hi));
}
} // namespace

Band parse_band(const std::string& text) {
  const auto dots = text.find("..");
  std::size_t used_lo = 0, used_hi = 0;
  Band b;
  try {
    if (dots == std::string::npos) throw std::invalid_argument("");
    const std::string lo = text.substr(0, dots), hi = text.substr(dots + 2);
    b.lo = std::stod(lo, &used_lo) + kZeroCelsius;
    b.hi = std::stod(hi, &used_hi) + kZeroCelsius;
    if (used_lo != lo.size() || used_hi != hi.size()) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw std::invalid_argument(
        fmt::format("--band: '{}' is not LO..HI in degC (e.g. 15..25)", text));
  }
  if (!(b.lo < b.hi))
    throw std::invalid_argument(
        fmt::format("--band: '{}': the low end must be below the high end", text));
  return b;
}

NodeSummary::NodeSummary(std::vector<std::string> names, std::vector<std::size_t> columns,
                         std::optional<Band> band)
    : names_(std::move(names)), columns_(std::move(columns)), band_(band), stats_(columns_.size()) {
}

void NodeSummary::add(double t, const std::vector<double>& temps) {
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    const double T = temps[columns_[c]];
    Stats& s = stats_[c];
    if (rows_ == 0) {
      s.min = s.max = s.last = T;
      s.t_min = s.t_max = t;
      continue;
    }
    if (T < s.min) s.min = T, s.t_min = t;
    if (T > s.max) s.max = T, s.t_max = t;
    s.integral += 0.5 * (s.last + T) * (t - t_last_);
    if (band_) s.outside += outside_time(t_last_, t, s.last, T, band_->lo, band_->hi);
    s.last = T;
  }
  if (rows_ == 0) t0_ = t;
  t_last_ = t;
  ++rows_;
}

std::vector<NodeStats> NodeSummary::results() const {
  std::vector<NodeStats> out;
  for (const Stats& s : stats_)
    out.push_back(
        {s.min, s.t_min, s.max, s.t_max, span() > 0.0 ? s.integral / span() : s.last, s.outside});
  return out;
}

std::string NodeSummary::csv(bool kelvin) const {
  const double offset = kelvin ? 0.0 : kZeroCelsius;
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out), "node,min,t_min,max,t_max,mean{}\n",
                 band_ ? ",time_outside,fraction_outside" : "");
  const std::vector<NodeStats> r = results();
  for (std::size_t c = 0; c < r.size(); ++c) {
    const NodeStats& s = r[c];
    append_csv_field(out, names_[columns_[c]]);
    fmt::format_to(std::back_inserter(out), ",{:.6f},{:.10g},{:.6f},{:.10g},{:.6f}", s.min - offset,
                   s.t_min, s.max - offset, s.t_max, s.mean - offset);
    if (band_)
      fmt::format_to(std::back_inserter(out), ",{:.10g},{:.6f}", s.outside,
                     span() > 0.0 ? s.outside / span() : 0.0);
    out.push_back('\n');
  }
  return fmt::to_string(out);
}

} // namespace thermnet::app
