// Estimator plugin 'tim-ab': the temperature at a point A that cannot carry a sensor (the heated
// surface) from three embedded sensors B, C, D equally spaced behind it (Sensors 2025, 25(7),
// 2227, "TIM-AB").
//
// The relation T_B = tau dT_C/dt + (xi + 1) T_C - xi T_D is fitted by least squares on B, C, D and
// applied one step up: T_A = tau dT_B/dt + (xi + 1) T_B - xi T_C. No material property is needed.
//
// mode=realtime (default): an overlapping window of the last N = round(t_w / dt) samples,
// t_w = eta tau (or `window` seconds), refitted every `slide` samples. Every row from the N-th on
// gets an estimate at that row, from the latest coefficients and the filtered B, dB/dt, C at the
// newest sample (so the estimate uses no future data). mode=full: one fit over the whole record,
// applied at every row (the study's full-time-domain inversion).
//
// Derivatives are never taken from raw noisy samples without care: `filter` chooses
// Savitzky-Golay (analytic derivative of the local polynomial, window gamma N, order `order`),
// Gaussian or moving average (then second-order differences), or none.

#include "kernel/estimation/estimator.hpp"
#include "plugins/estimator/arx_fit.hpp"
#include "plugins/estimator/filters.hpp"
#include "plugins/estimator/savgol_kernel.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace thermnet {
namespace {

using estimation::ArxCoefficients;
using estimation::FilterSpec;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

class TimAb final : public Estimator {
public:
  explicit TimAb(const EstimatorContext& ctx) {
    const EstimatorSettings& s = ctx.settings;
    auto sensors = s.list("sensors");
    if (sensors.size() != 3)
      throw EstimatorError(
          fmt::format("tim-ab needs three sensor columns B,C,D (nearest the surface first), got {}",
                      sensors.size()));
    for (int k = 0; k < 3; ++k)
      col_[k] = require_column(ctx.columns, sensors[k], "sensor");
    std::string truth = s.text("true");
    if (!truth.empty()) true_col_ = require_column(ctx.columns, truth, "true column");
    target_ = s.text("target", truth.empty() ? "A" : truth);
    std::string mode = s.text("mode", "realtime");
    if (mode != "realtime" && mode != "full")
      throw EstimatorError("tim-ab mode must be 'realtime' or 'full', got '" + mode + "'");
    full_ = mode == "full";
    double eta = s.number("eta", 4.0);
    if (s.has("window")) {
      window_s_ = s.number("window", 0.0);
    } else if (s.has("tau")) {
      double tau = s.number("tau", 0.0);
      if (!(tau > 0.0)) throw EstimatorError(fmt::format("tau must be > 0 s, got {:g}", tau));
      window_s_ = eta * tau;
    } else if (!full_) {
      throw EstimatorError("tim-ab realtime needs the window: give tau (with eta) or window");
    }
    if (!full_ && !(window_s_ > 0.0))
      throw EstimatorError(fmt::format("the window must be > 0 s, got {:g}", window_s_));
    double slide = s.number("slide", 10.0);
    if (!(slide >= 1.0) || slide != std::floor(slide) || slide > 1e9)
      throw EstimatorError(
          fmt::format("slide must be a whole number of samples >= 1, got {:g}", slide));
    slide_ = static_cast<std::size_t>(slide);
    try {
      filter_.kind = estimation::parse_filter(s.text("filter", "none"));
    } catch (const std::invalid_argument& e) {
      throw EstimatorError(e.what());
    }
    gamma_ = s.number("gamma", 0.5);
    if (!(gamma_ > 0.0 && gamma_ <= 1.0))
      throw EstimatorError(fmt::format("gamma must be in (0, 1], got {:g}", gamma_));
    double order = s.number("order", 3.0);
    if (!(order >= 0.0 && order <= 12.0) || order != std::floor(order))
      throw EstimatorError(fmt::format("order must be a whole number in 0..12, got {:g}", order));
    filter_.order = static_cast<int>(order);
  }

  std::vector<std::string> output_columns() const override {
    std::vector<std::string> c{target_ + "_est", "tau_hat", "xi_hat"};
    if (true_col_ >= 0) {
      c.push_back(target_ + "_true");
      c.push_back(target_ + "_err");
    }
    return c;
  }

  std::vector<EstimateRow> push(const std::vector<double>& row) override {
    double t = row[0];
    for (int k = 0; k < 3; ++k)
      if (std::isnan(row[col_[k]]))
        throw EstimatorError(fmt::format(
            "tim-ab needs every sample of the sensors; the row at t = {:g} s has none for "
            "sensor {}",
            t, "BCD"[k]));
    if (!t_.empty()) {
      double dt = t - t_.back();
      if (dt0_ == 0.0) dt0_ = dt;
      if (std::abs(dt - dt0_) > 0.05 * dt0_)
        throw EstimatorError(fmt::format(
            "tim-ab needs uniform sampling: step {:g} s at t = {:g} s, earlier steps {:g} s", dt, t,
            dt0_));
    }
    t_.push_back(t);
    for (int k = 0; k < 3; ++k)
      y_[k].push_back(row[col_[k]]);
    truth_.push_back(true_col_ >= 0 ? row[true_col_] : nan);
    ++rows_seen_;
    if (full_) return {};
    return {realtime_step()};
  }

  std::vector<EstimateRow> finish() override {
    if (!full_) return {};
    std::size_t n = t_.size();
    if (n < 4) throw EstimatorError(fmt::format("tim-ab needs at least 4 rows, got {}", n));
    auto start = std::chrono::steady_clock::now();
    double dt = (t_.back() - t_.front()) / static_cast<double>(n - 1);
    FilterSpec spec = filter_for(n);
    filter_block(0, n, spec, dt);
    coeff_ = estimation::fit_arx(v_[0].data(), v_[1].data(), d_[1].data(), v_[2].data(), n);
    ++windows_;
    if (!coeff_.ok) throw EstimatorError("tim-ab: the sensor data are degenerate (constant)");
    std::vector<EstimateRow> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
      out.push_back(make_row(
          t_[i], estimation::arx_extrapolate(coeff_, v_[0][i], d_[0][i], v_[1][i]), truth_[i]));
    record_time(start);
    return out;
  }

  std::vector<EstimateMetric> metrics() const override {
    std::vector<EstimateMetric> m{
        {"rows", static_cast<double>(rows_seen_), ""},
        {"estimated_rows", static_cast<double>(estimated_), ""},
        {"windows", static_cast<double>(windows_), ""},
        {"window_samples", static_cast<double>(full_ ? t_.size() : window_n_), ""},
        {"tau_hat", coeff_.tau, "s"},
        {"xi_hat", coeff_.xi, ""},
        {"window_time_mean", windows_ ? time_sum_ / static_cast<double>(windows_) : 0.0, "s"},
        {"window_time_max", time_max_, "s"}};
    if (!full_ && rows_seen_ > 0) {
      m.push_back({"row_time_mean", row_time_sum_ / static_cast<double>(rows_seen_), "s"});
      m.push_back({"row_time_max", row_time_max_, "s"});
    }
    if (true_col_ >= 0 && compared_ > 0) {
      m.push_back({"mean_relative_error", 100.0 * rel_sum_ / static_cast<double>(rel_count_), "%"});
      if (windows_scored_ > 0)
        m.push_back({"window_relative_error",
                     100.0 * window_rel_sum_ / static_cast<double>(windows_scored_), "%"});
      m.push_back({"rmse", std::sqrt(sq_sum_ / static_cast<double>(compared_)), "K"});
      m.push_back({"max_abs_error", max_abs_, "K"});
      m.push_back({"mean_abs_error", abs_sum_ / static_cast<double>(compared_), "K"});
    }
    return m;
  }

private:
  FilterSpec filter_for(std::size_t n) const {
    FilterSpec spec = filter_;
    spec.window = static_cast<int>(std::lround(gamma_ * static_cast<double>(n)));
    return estimation::clamp_filter(spec, n);
  }

  // Filters samples [first, first + n) of B, C, D into v_, d_ (indices from 0).
  void filter_block(std::size_t first, std::size_t n, const FilterSpec& spec, double dt) {
    for (int k = 0; k < 3; ++k) {
      v_[k].resize(n);
      d_[k].resize(n);
      estimation::apply_filter(spec, y_[k].data() + first, n, dt, v_[k].data(), d_[k].data());
    }
  }

  // Savitzky-Golay in a sliding window: the centred value and slope of sample n - 1 - h, computed
  // once when sample n - 1 arrives (windows overlap, so this is the work they share).
  void update_savgol_cache() {
    const std::size_t n = t_.size(), W = static_cast<std::size_t>(sg_.window());
    for (int k = 0; k < 3; ++k) {
      cv_[k].resize(n, nan);
      cd_[k].resize(n, nan);
      if (n < W) continue;
      auto [v, s] = sg_.centre(y_[k].data() + (n - W));
      cv_[k][n - 1 - static_cast<std::size_t>(sg_.half())] = v;
      cd_[k][n - 1 - static_cast<std::size_t>(sg_.half())] = s;
    }
  }

  EstimateRow realtime_step() {
    auto start = std::chrono::steady_clock::now();
    std::size_t n = t_.size();
    if (window_n_ == 0 && n >= 2) {
      window_n_ = static_cast<std::size_t>(std::lround(window_s_ / dt0_)) + 1;
      if (window_n_ < 4) window_n_ = 4;
      spec_ = filter_for(window_n_);
      if (spec_.kind == estimation::FilterKind::savgol && spec_.window >= 3)
        sg_ = estimation::SavgolKernel(spec_.window, spec_.order);
    }
    if (sg_.window() > 0) update_savgol_cache();
    if (window_n_ == 0 || n < window_n_) {
      record_row_time(start);
      return make_row(t_.back(), nan, truth_.back(), false);
    }
    std::size_t first = n - window_n_;
    double dt = (t_.back() - t_[first]) / static_cast<double>(window_n_ - 1);
    bool refit = since_fit_ == 0 || since_fit_ >= slide_;
    double est = nan;
    if (refit) {
      if (sg_.window() > 0) {
        for (int k = 0; k < 3; ++k) {
          v_[k].resize(window_n_);
          d_[k].resize(window_n_);
          estimation::savgol_window(sg_, y_[k].data() + first, cv_[k].data() + first,
                                    cd_[k].data() + first, window_n_, dt, v_[k].data(),
                                    d_[k].data());
        }
      } else {
        filter_block(first, window_n_, spec_, dt);
      }
      coeff_ =
          estimation::fit_arx(v_[0].data(), v_[1].data(), d_[1].data(), v_[2].data(), window_n_);
      ++windows_;
      since_fit_ = 0;
      std::size_t last = window_n_ - 1;
      if (coeff_.ok)
        est = estimation::arx_extrapolate(coeff_, v_[0][last], d_[0][last], v_[1][last]);
    } else if (sg_.window() > 0) {
      const std::size_t W = static_cast<std::size_t>(sg_.window());
      auto [vb, db] = sg_.newest(y_[0].data() + (n - W));
      double vc = sg_.newest(y_[1].data() + (n - W)).first;
      if (coeff_.ok) est = estimation::arx_extrapolate(coeff_, vb, db / dt, vc);
    } else {
      std::size_t tail = std::min(window_n_, estimation::filter_support(spec_));
      tail_v_.resize(tail);
      tail_d_.resize(tail);
      double vb = 0.0, db = 0.0;
      estimation::apply_filter(spec_, y_[0].data() + (n - tail), tail, dt, tail_v_.data(),
                               tail_d_.data());
      vb = tail_v_.back();
      db = tail_d_.back();
      estimation::apply_filter(spec_, y_[1].data() + (n - tail), tail, dt, tail_v_.data(),
                               tail_d_.data());
      if (coeff_.ok) est = estimation::arx_extrapolate(coeff_, vb, db, tail_v_.back());
    }
    ++since_fit_;
    if (refit) {
      record_time(start);
      if (true_col_ >= 0 && coeff_.ok) score_window(first);
    }
    record_row_time(start);
    trim();
    return make_row(t_.back(), est, truth_.back(), coeff_.ok);
  }

  // The study's "mean relative error of the window": the window's fit applied to every row of the
  // window (its full-time-domain inversion), mean of |error| / |rise of the truth| over the rows.
  void score_window(std::size_t first) {
    if (std::isnan(reference_)) reference_ = truth_.front();
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < window_n_; ++i) {
      double truth = truth_[first + i], rise = std::abs(truth - reference_);
      if (std::isnan(truth) || !(rise > 1e-9)) continue;
      double est = estimation::arx_extrapolate(coeff_, v_[0][i], d_[0][i], v_[1][i]);
      sum += std::abs(est - truth) / rise;
      ++count;
    }
    if (count == 0) return;
    window_rel_sum_ += sum / static_cast<double>(count);
    ++windows_scored_;
  }

  // Keeps the stored history bounded in realtime mode (the window plus slack).
  void trim() {
    std::size_t keep = window_n_ + 16;
    if (t_.size() < 4 * keep) return;
    std::size_t drop = t_.size() - keep;
    auto cut = [drop](std::vector<double>& v) {
      v.erase(v.begin(), v.begin() + static_cast<long>(drop));
    };
    cut(t_);
    cut(truth_);
    for (int k = 0; k < 3; ++k) {
      cut(y_[k]);
      if (sg_.window() > 0) {
        cut(cv_[k]);
        cut(cd_[k]);
      }
    }
  }

  // Wall time of one refit (filter + fit + estimate).
  void record_time(std::chrono::steady_clock::time_point start) {
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    time_sum_ += s;
    time_max_ = std::max(time_max_, s);
  }

  // Wall time of one realtime row, refit or not (all the work a new sample causes).
  void record_row_time(std::chrono::steady_clock::time_point start) {
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    row_time_sum_ += s;
    row_time_max_ = std::max(row_time_max_, s);
  }

  EstimateRow make_row(double t, double est, double truth, bool have = true) {
    EstimateRow r;
    r.time = t;
    if (!have) est = nan;
    r.values = {est, have ? coeff_.tau : nan, have ? coeff_.xi : nan};
    if (true_col_ >= 0) {
      double err = est - truth;
      r.values.push_back(truth);
      r.values.push_back(err);
      if (!std::isnan(err)) {
        if (std::isnan(reference_)) reference_ = truth_.front();
        ++compared_;
        sq_sum_ += err * err;
        abs_sum_ += std::abs(err);
        max_abs_ = std::max(max_abs_, std::abs(err));
        double rise = std::abs(truth - reference_);
        if (rise > 1e-9) {
          rel_sum_ += std::abs(err) / rise;
          ++rel_count_;
        }
      }
    }
    if (!std::isnan(est)) ++estimated_;
    return r;
  }

  int col_[3] = {0, 0, 0};
  int true_col_ = -1;
  std::string target_;
  bool full_ = false;
  double window_s_ = 0.0, gamma_ = 0.5, dt0_ = 0.0;
  std::size_t slide_ = 10, window_n_ = 0, since_fit_ = 0;
  FilterSpec filter_, spec_;
  estimation::SavgolKernel sg_; // realtime Savitzky-Golay kernels (window 0: not used)
  std::vector<double> t_, truth_, y_[3], v_[3], d_[3], tail_v_, tail_d_;
  std::vector<double> cv_[3], cd_[3]; // centred Savitzky-Golay value and slope per sample
  ArxCoefficients coeff_;
  std::size_t rows_seen_ = 0, windows_ = 0, estimated_ = 0, compared_ = 0, rel_count_ = 0,
              windows_scored_ = 0;
  double time_sum_ = 0.0, time_max_ = 0.0, sq_sum_ = 0.0, abs_sum_ = 0.0, max_abs_ = 0.0,
         rel_sum_ = 0.0, reference_ = nan, row_time_sum_ = 0.0, row_time_max_ = 0.0,
         window_rel_sum_ = 0.0;
};

EstimatorPlugin tim_ab_plugin() {
  EstimatorPlugin p;
  p.name = "tim-ab";
  p.doc = "surface temperature A from sensors B, C, D behind it (ARX fit, full or sliding window)";
  p.options = {{"sensors", "", "three sensor columns B,C,D, nearest the surface first (required)"},
               {"true", "", "column holding the true A, for errors (optional)"},
               {"target", "A", "name of the estimated point in the output columns"},
               {"mode", "realtime", "realtime (sliding window) or full (one fit over the record)"},
               {"tau", "", "thermal hysteresis time rho c z_AB (z_AB + z_BC) / (2 k), s"},
               {"eta", "4", "window length in units of tau (t_w = eta tau)"},
               {"window", "", "window length t_w in s (instead of eta and tau)"},
               {"slide", "10", "slide step of the window, samples"},
               {"filter", "none", "none, savgol, gaussian or moving-average"},
               {"gamma", "0.5", "filter window as a fraction of the inversion window"},
               {"order", "3", "Savitzky-Golay polynomial order"}};
  p.create = [](const EstimatorContext& ctx) { return std::make_unique<TimAb>(ctx); };
  return p;
}

} // namespace

THERMNET_REGISTER(EstimatorPlugin, tim_ab_plugin);

} // namespace thermnet
