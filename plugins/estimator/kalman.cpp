// Estimator plugin 'ekf': extended Kalman filter (and Rauch-Tung-Striebel smoother) over a
// thermal network model -- the digital twin. From the measured nodes it estimates every unknown
// node (e.g. lens centres that cannot carry sensors) and, optionally, an unknown heat input.
//
// State: the unknown node temperatures T (K), plus q (W) when `input` names a node: an extra heat
// flow into that node, modelled as a random walk. Dynamics C dT/dt = F(t, T) + e q.
//
// The filter is the one every command shares (kernel/core/network_state_space.hpp,
// kalman_filter.hpp). Propagation between two measurement times t_k -> t_k+1:
//  - mean: the network's own integrator (CVODE BDF via thermnet::integrate), which keeps the
//    nonlinear elements (radiation, convection correlations), time-varying inputs, breakpoints and
//    thermostat events exact to the solver tolerance;
//  - covariance: the network linearised at the posterior mean with its analytic Jacobian,
//    A = C^-1 dF/dT, discretised exactly by matrix exponentials (Van Loan 1978):
//    Phi = exp(A h), Q_d = int_0^h exp(A s) Q_c exp(A' s) ds, with Q_c = diag(process^2) K^2/s
//    on the nodes and input_noise^2 W^2/s on q.
// Update: the measured columns of the row (missing cells skipped), R = sigma_meas^2 I, Joseph
// form. Smoother (`smooth`): RTS backward pass over the stored filter steps, batch only.
// Algebraic (C = 0) nodes are not supported by the covariance propagation and are rejected.

#include "kernel/core/network.hpp"
#include "kernel/core/network_state_space.hpp"
#include "kernel/core/simulation.hpp"
#include "kernel/estimation/estimator.hpp"
#include "lang/units.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

namespace thermnet {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

struct Step {
  double time;
  Eigen::VectorXd x_post, x_prior_next; // x(k|k), x(k+1|k)
  Eigen::MatrixXd P_post, P_prior_next, Phi;
};

class Ekf final : public Estimator {
public:
  explicit Ekf(const EstimatorContext& ctx) : net_(*ctx.network) {
    const EstimatorSettings& s = ctx.settings;
    n_ = net_.size();
    auto unknown_of = [&](const std::string& name) {
      int spec = net_.spec().node_index(name);
      for (std::size_t i = 0; i < net_.unknown_nodes().size(); ++i)
        if (net_.unknown_nodes()[i] == spec) return static_cast<int>(i);
      return -1;
    };
    std::string input = s.text("input");
    if (!input.empty()) {
      input_ = unknown_of(input);
      if (input_ < 0)
        throw EstimatorError(fmt::format("ekf: input node '{}' is not a node of the model", input));
    }
    try {
      model_ = std::make_unique<NetworkStateSpace>(net_, input_);
    } catch (const std::invalid_argument& e) {
      throw EstimatorError(fmt::format("ekf: {}", e.what()));
    }
    m_ = model_->size();
    // Measured columns: the named ones, else every data column that names a node.
    auto measured = s.list("measured");
    if (measured.empty())
      for (std::size_t c = 1; c < ctx.columns.size(); ++c)
        if (unknown_of(ctx.columns[c]) >= 0) measured.push_back(ctx.columns[c]);
    if (measured.empty()) throw EstimatorError("ekf: no data column names a node of the model");
    for (const auto& name : measured) {
      int col = require_column(ctx.columns, name, "measured node");
      int u = unknown_of(name);
      if (u < 0)
        throw EstimatorError(
            fmt::format("ekf: measured column '{}' is not a node of the model", name));
      meas_.push_back({col, u});
    }
    for (std::size_t c = 1; c < ctx.columns.size(); ++c) {
      int u = unknown_of(ctx.columns[c]);
      bool is_measured = false;
      for (auto [col, unk] : meas_)
        is_measured |= col == static_cast<int>(c);
      if (u >= 0 && !is_measured) truth_.push_back({static_cast<int>(c), u});
    }
    sigma_meas_ = positive(s, "sigma-meas", 0.1);
    process_ = nonnegative(s, "process", 0.01);
    input_noise_ = nonnegative(s, "input-noise", 0.05);
    double sigma0 = positive(s, "sigma0", 2.0);
    double input_sigma0 = positive(s, "input-sigma0", 10.0);
    smooth_ = s.flag("smooth");
    solver_.rtol = 1e-8;
    solver_.atol = 1e-8;
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(m_);
    auto T0 = start_state(net_, solver_); // the same start as every other command
    for (int i = 0; i < n_; ++i)
      x0(i) = T0[i];
    if (input_ >= 0) x0(n_) = s.number("input0", 0.0);
    Eigen::MatrixXd P0 = Eigen::MatrixXd::Zero(m_, m_);
    for (int i = 0; i < n_; ++i)
      P0(i, i) = sigma0 * sigma0;
    if (input_ >= 0) P0(n_, n_) = input_sigma0 * input_sigma0;
    filter_ = std::make_unique<KalmanFilter>(std::move(x0), std::move(P0));
    Qc_ = Eigen::MatrixXd::Zero(m_, m_);
    for (int i = 0; i < n_; ++i)
      Qc_(i, i) = process_ * process_;
    if (input_ >= 0) Qc_(n_, n_) = input_noise_ * input_noise_;
    err_sq_.assign(truth_.size(), 0.0);
    err_n_.assign(truth_.size(), 0);
  }

  std::vector<std::string> output_columns() const override {
    std::vector<std::string> c;
    for (int i = 0; i < n_; ++i)
      c.push_back(net_.unknown_name(i));
    if (input_ >= 0) c.push_back("q_" + net_.unknown_name(input_));
    for (int i = 0; i < n_; ++i)
      c.push_back("sd_" + net_.unknown_name(i));
    if (input_ >= 0) c.push_back("sd_q_" + net_.unknown_name(input_));
    return c;
  }

  std::vector<EstimateRow> push(const std::vector<double>& row) override {
    double t = row[0];
    auto start = std::chrono::steady_clock::now();
    if (started_) {
      Discretised d = model_->predict(*filter_, t_, t, Qc_, solver_);
      if (smooth_) {
        steps_.back().x_prior_next = filter_->x();
        steps_.back().P_prior_next = filter_->P();
        steps_.back().Phi = std::move(d.Phi);
      }
    }
    started_ = true;
    t_ = t;
    update(row);
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    time_sum_ += s;
    time_max_ = std::max(time_max_, s);
    ++rows_;
    if (smooth_) {
      steps_.push_back({t, filter_->x(), {}, filter_->P(), {}, {}});
      truth_rows_.push_back(row);
      return {};
    }
    score(row, filter_->x());
    return {make_row(t, filter_->x(), filter_->P())};
  }

  std::vector<EstimateRow> finish() override {
    if (!smooth_ || steps_.empty()) return {};
    std::size_t N = steps_.size();
    std::vector<EstimateRow> out(N);
    Eigen::VectorXd xs = steps_[N - 1].x_post;
    Eigen::MatrixXd Ps = steps_[N - 1].P_post;
    out[N - 1] = make_row(steps_[N - 1].time, xs, Ps);
    score(truth_rows_[N - 1], xs);
    for (std::size_t k = N - 1; k-- > 0;) {
      const Step& st = steps_[k];
      Eigen::MatrixXd G =
          st.P_prior_next.ldlt().solve(st.Phi * st.P_post).transpose(); // P Phi' Pp^-1
      xs = st.x_post + G * (xs - st.x_prior_next);
      Ps = st.P_post + G * (Ps - st.P_prior_next) * G.transpose();
      Ps = 0.5 * (Ps + Ps.transpose());
      out[k] = make_row(st.time, xs, Ps);
      score(truth_rows_[k], xs);
    }
    return out;
  }

  std::vector<EstimateMetric> metrics() const override {
    std::vector<EstimateMetric> m{
        {"rows", static_cast<double>(rows_), ""},
        {"step_time_mean", rows_ ? time_sum_ / static_cast<double>(rows_) : 0.0, "s"},
        {"step_time_max", time_max_, "s"}};
    double all_sq = 0.0;
    std::size_t all_n = 0;
    for (std::size_t j = 0; j < truth_.size(); ++j) {
      if (!err_n_[j]) continue;
      m.push_back({"rmse_" + net_.unknown_name(truth_[j].unknown),
                   std::sqrt(err_sq_[j] / static_cast<double>(err_n_[j])), "K"});
      all_sq += err_sq_[j];
      all_n += err_n_[j];
    }
    if (all_n) m.push_back({"rmse_hidden", std::sqrt(all_sq / static_cast<double>(all_n)), "K"});
    if (input_ >= 0) m.push_back({"input_final", filter_->x()(n_), "W"});
    return m;
  }

private:
  struct Link {
    int column;
    int unknown;
  };

  static double positive(const EstimatorSettings& s, const std::string& k, double d) {
    double v = s.number(k, d);
    if (!(v > 0.0)) throw EstimatorError(fmt::format("ekf: {} must be > 0, got {:g}", k, v));
    return v;
  }
  static double nonnegative(const EstimatorSettings& s, const std::string& k, double d) {
    double v = s.number(k, d);
    if (!(v >= 0.0)) throw EstimatorError(fmt::format("ekf: {} must be >= 0, got {:g}", k, v));
    return v;
  }

  void update(const std::vector<double>& row) {
    std::vector<Link> present;
    for (const Link& l : meas_)
      if (!std::isnan(row[l.column])) present.push_back(l);
    if (present.empty()) return;
    const auto p = static_cast<Eigen::Index>(present.size());
    std::vector<int> states;
    Eigen::VectorXd y(p);
    for (Eigen::Index r = 0; r < p; ++r) {
      states.push_back(present[r].unknown);
      y(r) = row[present[r].column] + lang::kZeroCelsius;
    }
    filter_->update(states, y, Eigen::VectorXd::Constant(p, sigma_meas_ * sigma_meas_));
  }

  void score(const std::vector<double>& row, const Eigen::VectorXd& x) {
    for (std::size_t j = 0; j < truth_.size(); ++j) {
      double truth = row[truth_[j].column];
      if (std::isnan(truth)) continue;
      double e = x(truth_[j].unknown) - lang::kZeroCelsius - truth;
      err_sq_[j] += e * e;
      ++err_n_[j];
    }
  }

  EstimateRow make_row(double t, const Eigen::VectorXd& x, const Eigen::MatrixXd& P) const {
    EstimateRow r;
    r.time = t;
    for (int i = 0; i < n_; ++i)
      r.values.push_back(x(i) - lang::kZeroCelsius);
    if (input_ >= 0) r.values.push_back(x(n_));
    for (int i = 0; i < m_; ++i)
      r.values.push_back(std::sqrt(std::max(0.0, P(i, i))));
    return r;
  }

  Network net_;
  std::unique_ptr<NetworkStateSpace> model_;
  std::unique_ptr<KalmanFilter> filter_;
  Eigen::MatrixXd Qc_;
  int n_ = 0, m_ = 0, input_ = -1;
  std::vector<Link> meas_, truth_;
  double sigma_meas_ = 0.1, process_ = 0.01, input_noise_ = 0.05;
  bool smooth_ = false, started_ = false;
  SolverOptions solver_;
  double t_ = 0.0;
  std::vector<Step> steps_;
  std::vector<std::vector<double>> truth_rows_;
  std::vector<double> err_sq_;
  std::vector<std::size_t> err_n_;
  std::size_t rows_ = 0;
  double time_sum_ = 0.0, time_max_ = 0.0;
};

EstimatorPlugin ekf_plugin() {
  EstimatorPlugin p;
  p.name = "ekf";
  p.doc = "extended Kalman filter (+ RTS smoother) over the model: hidden nodes, unknown input";
  p.needs_model = true;
  p.options = {
      {"measured", "", "data columns used as measurements (default: every node column)"},
      {"input", "", "node receiving an unknown extra heat input q (random walk), estimated"},
      {"smooth", "no", "Rauch-Tung-Striebel smoother over the whole record (batch only)"},
      {"sigma-meas", "0.1", "standard deviation of the sensors, K"},
      {"process", "0.01", "process noise on every node, K/sqrt(s)"},
      {"input-noise", "0.05", "random-walk rate of the unknown input, W/sqrt(s)"},
      {"sigma0", "2", "initial standard deviation of the node temperatures, K"},
      {"input0", "0", "initial guess of the unknown input, W"},
      {"input-sigma0", "10", "initial standard deviation of the unknown input, W"}};
  p.create = [](const EstimatorContext& ctx) -> std::unique_ptr<Estimator> {
    if (!ctx.network) throw EstimatorError("ekf needs a model");
    return std::make_unique<Ekf>(ctx);
  };
  return p;
}

} // namespace

THERMNET_REGISTER(EstimatorPlugin, ekf_plugin);

} // namespace thermnet
