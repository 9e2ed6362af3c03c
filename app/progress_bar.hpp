#pragma once
/// A one-line progress bar on standard error for long runs (calibrate): percent, evaluations, ETA
/// and best RMSE so far; or a line saying what a run is doing (diagnose).

#include "kernel/calibration/optimizer.hpp"

#include <chrono>
#include <mutex>
#include <string>

namespace thermnet::app {

/// True when progress should be drawn: stderr is a terminal and the CI variable is unset.
bool progress_wanted();

/// The bar's text for a state: "[#####.....]  45%  1350/3000  ETA 0:12  best RMSE 1.234 K".
std::string format_progress(const Progress& p, double elapsed_s);

/// Draws progress on stderr, at most about ten times a second; silent when disabled.
class ProgressBar {
public:
  /// A bar that draws only when `enabled` (normally progress_wanted()).
  explicit ProgressBar(bool enabled);
  /// Clears the line if anything was drawn.
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Reports progress; thread-safe (a call finding another one drawing is skipped).
  void update(const Progress& p);
  /// Draws a line of text instead (what a run is doing), at most about ten times a second unless
  /// `force`; thread-safe like update().
  void show(const std::string& text, bool force = false);
  /// Seconds since the bar was made.
  double elapsed() const;
  /// Clears the bar's line (idempotent).
  void finish();

private:
  bool enabled_;
  bool drawn_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_;
};

} // namespace thermnet::app
