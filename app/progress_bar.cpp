#include "app/progress_bar.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>

namespace thermnet::app {

namespace {

constexpr int kBarWidth = 24;
constexpr auto kRedrawInterval = std::chrono::milliseconds(100);

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--";
  auto total = static_cast<long long>(std::llround(s));
  long long h = total / 3600, m = total / 60 % 60, sec = total % 60;
  return h > 0 ? fmt::format("{}:{:02}:{:02}", h, m, sec) : fmt::format("{}:{:02}", m, sec);
}

} // namespace

bool progress_wanted() {
  return ::isatty(STDERR_FILENO) && std::getenv("CI") == nullptr;
}

std::string format_progress(const Progress& p, double elapsed_s) {
  const std::string best =
      std::isnan(p.best_rmse) ? std::string("none yet") : fmt::format("{:.4g} K", p.best_rmse);
  if (p.total == 0) // budget unknown: no bar, no ETA
    return fmt::format("{} evaluations  {:.0f} s  best RMSE {}", p.done, elapsed_s, best);
  const double frac = std::min(1.0, static_cast<double>(p.done) / static_cast<double>(p.total));
  const int filled = static_cast<int>(frac * kBarWidth);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kBarWidth - filled), '.');
  const double eta =
      p.done > 0 && p.total >= p.done
          ? elapsed_s * static_cast<double>(p.total - p.done) / static_cast<double>(p.done)
          : NAN;
  return fmt::format("[{}] {:3.0f}%  {}/{}  ETA {}  best RMSE {}", bar, 100.0 * frac, p.done,
                     p.total, format_duration(eta), best);
}

ProgressBar::ProgressBar(bool enabled)
    : enabled_(enabled), start_(std::chrono::steady_clock::now()), last_() {}

ProgressBar::~ProgressBar() {
  finish();
}

void ProgressBar::update(const Progress& p) {
  if (!enabled_) return;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_ < kRedrawInterval && p.done != p.total) return;
  last_ = now;
  drawn_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const std::string line = fmt::format("\r{}\033[K", format_progress(p, elapsed));
  std::fwrite(line.data(), 1, line.size(), stderr);
  std::fflush(stderr);
}

void ProgressBar::show(const std::string& text, bool force) {
  if (!enabled_) return;
  // A forced line waits for one being drawn; another is skipped when one is being drawn.
  std::unique_lock lock(mutex_, std::defer_lock);
  if (force)
    lock.lock();
  else if (!lock.try_lock())
    return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_ < kRedrawInterval && !force) return;
  last_ = now;
  drawn_ = true;
  const std::string line = fmt::format("\r{}\033[K", text);
  std::fwrite(line.data(), 1, line.size(), stderr);
  std::fflush(stderr);
}

double ProgressBar::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressBar::finish() {
  std::lock_guard lock(mutex_);
  if (!drawn_) return;
  drawn_ = false;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
}

} // namespace thermnet::app
