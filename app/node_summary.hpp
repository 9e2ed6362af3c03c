#pragma once
/// Per-node summary of a run, accumulated row by row: min, max and their times, time-weighted mean
/// (trapezoidal over the output rows) and, with a band, the time spent outside it (crossings
/// interpolated linearly between rows).

#include <optional>
#include <string>
#include <vector>

namespace thermnet::app {

/// A temperature band, K.
struct Band {
  double lo = 0.0; ///< lower limit, K
  double hi = 0.0; ///< upper limit, K
};

/// Parses "LO..HI" in degC (e.g. "15..25", "-10..5.5"); throws std::invalid_argument.
Band parse_band(const std::string& text);

/// The summary of one node, K and s.
struct NodeStats {
  double min = 0.0;     ///< lowest temperature, K
  double t_min = 0.0;   ///< when, s (the first time)
  double max = 0.0;     ///< highest temperature, K
  double t_max = 0.0;   ///< when, s
  double mean = 0.0;    ///< time-weighted mean, K
  double outside = 0.0; ///< time outside the band, s (0 without a band)
};

/// Accumulates the summary of selected columns over output rows.
class NodeSummary {
public:
  /// Summarises columns `columns` (indices into each row) named `names` (all nodes).
  NodeSummary(std::vector<std::string> names, std::vector<std::size_t> columns,
              std::optional<Band> band);
  /// Adds one output row: time (s) and every node's temperature (K).
  void add(double t, const std::vector<double>& temps);
  /// The CSV: node,min,t_min,max,t_max,mean[,time_outside,fraction_outside], temperatures in
  /// degC (or K with `kelvin`), times in s.
  std::string csv(bool kelvin) const;
  /// The summary of each selected column, in `columns` order.
  std::vector<NodeStats> results() const;
  /// Whether a band was given.
  bool has_band() const { return band_.has_value(); }
  /// Time covered by the rows, s.
  double span() const { return t_last_ - t0_; }

private:
  struct Stats {
    double min = 0.0, t_min = 0.0, max = 0.0, t_max = 0.0, integral = 0.0, outside = 0.0;
    double last = 0.0;
  };
  std::vector<std::string> names_;
  std::vector<std::size_t> columns_;
  std::optional<Band> band_;
  std::vector<Stats> stats_;
  double t0_ = 0.0, t_last_ = 0.0;
  std::size_t rows_ = 0;
};

} // namespace thermnet::app
