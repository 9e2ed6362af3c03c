// PredictionProblem: every case filtered by the shared (extended) Kalman filter, its one-step
// predictions and log-likelihood; fit_prediction(): their maximum by the bounded quasi-Newton
// method, standard errors from the Hessian; the likelihood-ratio test.

#include "kernel/calibration/prediction_error.hpp"

#include "kernel/core/exact_linear.hpp"

#include "kernel/calibration/quasi_newton.hpp"
#include "kernel/core/integrator.hpp"
#include "kernel/core/measured_data.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/network_state_space.hpp"
#include "kernel/core/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>

namespace thermnet {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Bounds and starts of the noise intensities (log scale): wide enough for a well-measured
// laboratory rig and a building alike.
constexpr double kProcessLo = 1e-9, kProcessHi = 1.0;        // K/sqrt(s)
constexpr double kMeasurementLo = 1e-5, kMeasurementHi = 10; // K

// Unknown index of each spec node (-1: a boundary or a node without an unknown).
std::vector<int> unknown_of_spec(const Network& net) {
  std::vector<int> u(net.spec().nodes.size(), -1);
  for (std::size_t i = 0; i < net.unknown_nodes().size(); ++i)
    u[static_cast<std::size_t>(net.unknown_nodes()[i])] = static_cast<int>(i);
  return u;
}

double median_step(const std::vector<MeasuredData>& data) {
  std::vector<double> dt;
  for (const auto& d : data)
    for (std::size_t k = 1; k < d.times.size(); ++k)
      dt.push_back(d.times[k] - d.times[k - 1]);
  if (dt.empty()) return 1.0;
  std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
  return std::max(dt[dt.size() / 2], 1e-6);
}

// Regularised upper incomplete gamma Q(a, x) (series below a + 1, continued fraction above).
double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  const double lg = std::lgamma(a);
  if (x < a + 1) {
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 1000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(-x + a * std::log(x) - lg));
  }
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < 1e-16) break;
  }
  return std::exp(-x + a * std::log(x) - lg) * h;
}

} // namespace

PredictionProblem::PredictionProblem(std::vector<PredictionParam> structural, SpecMaker make,
                                     std::vector<std::string> cases, std::vector<MeasuredData> data,
                                     PredictionSettings settings)
    : params_(std::move(structural)), make_(std::move(make)), cases_(std::move(cases)),
      data_(std::move(data)), settings_(settings) {
  structural_ = params_.size();
  if (cases_.size() != data_.size())
    throw std::invalid_argument("a prediction problem needs one data set per case");
  add_noise_params();
}

PredictionProblem::PredictionProblem(const lang::Model& model, const CalibrationProblem& problem,
                                     PredictionSettings settings)
    : make_([&model, &problem](std::size_t c, const std::vector<double>& x) {
        return model.instantiate(problem.cases()[c], problem.values(x));
      }),
      cases_(problem.cases()), data_(problem.data()), settings_(settings) {
  for (const auto& p : problem.params()) {
    PredictionParam q;
    q.name = p.name;
    q.box.lo = *p.lo;
    q.box.hi = *p.hi;
    q.box.scale = *p.lo > 0 ? ParamScale::log : ParamScale::linear;
    q.start = p.value;
    params_.push_back(std::move(q));
  }
  structural_ = params_.size();
  add_noise_params();
}

void PredictionProblem::add_noise_params() {
  cache_ = make_cache();
  if (cases_.empty()) throw std::invalid_argument("no case with data to filter");
  std::vector<double> x0;
  for (const auto& p : params_)
    x0.push_back(p.start);
  Network net(make_(0, x0));
  NetworkStateSpace check(net); // rejects arithmetic nodes, naming them
  for (int i = 0; i < net.temperature_count(); ++i)
    process_nodes_.push_back(net.unknown_name(i));
  const std::vector<int> unknown = unknown_of_spec(net);
  for (const auto& d : data_)
    for (const auto& s : d.series)
      if (s.node_index >= 0 && unknown[static_cast<std::size_t>(s.node_index)] >= 0 &&
          std::find(measured_nodes_.begin(), measured_nodes_.end(), s.node) ==
              measured_nodes_.end())
        measured_nodes_.push_back(s.node);
  if (measured_nodes_.empty())
    throw std::invalid_argument("the data measure no node of the model (only boundaries)");
  const double h = median_step(data_);
  for (const auto& name : process_nodes_) {
    PredictionParam q;
    q.name = "sigma_w[" + name + "]";
    q.box = {kProcessLo, kProcessHi, ParamScale::log};
    q.start = std::clamp(0.1 / std::sqrt(h), 10 * kProcessLo, 0.1 * kProcessHi);
    q.noise = true;
    params_.push_back(std::move(q));
  }
  for (const auto& name : measured_nodes_) {
    PredictionParam q;
    q.name = "sigma_v[" + name + "]";
    q.box = {kMeasurementLo, kMeasurementHi, ParamScale::log};
    q.start = 0.1;
    q.noise = true;
    params_.push_back(std::move(q));
  }
}

std::vector<BoundedParam> PredictionProblem::boxes() const {
  std::vector<BoundedParam> b;
  for (const auto& p : params_)
    b.push_back(p.box);
  return b;
}

std::vector<double> PredictionProblem::start() const {
  std::vector<double> s;
  for (const auto& p : params_)
    s.push_back(p.start);
  return s;
}

std::size_t PredictionProblem::points() const {
  std::size_t n = 0;
  for (const auto& d : data_)
    for (const auto& s : d.series)
      if (std::find(measured_nodes_.begin(), measured_nodes_.end(), s.node) !=
          measured_nodes_.end())
        for (double v : s.values)
          n += std::isnan(v) ? 0 : 1;
  return n;
}

namespace prediction_detail {

/// A measured series as the filter sees it: y = H x + offset (a node's temperature, or a
/// sensor's reading through its lag, offset and gain: affine in the unknowns).
struct Observation {
  std::size_t series = 0; ///< index into the case's data
  std::size_t node = 0;   ///< index into the measured nodes (its noise)
  Eigen::RowVectorXd H;   ///< d reading / d unknowns
  double offset = 0.0;    ///< the reading at zero unknowns
};

/// The sensor element a series is read through in `net`: the data's own, else the only sensor of
/// the network reading its node alone (a sensor a diagnosis candidate added), else none (-1).
int reading_sensor(const Network& net, const MeasuredSeries& s) {
  if (s.sensor >= 0) return s.sensor;
  int found = -1;
  const auto& elements = net.spec().elements;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const auto& el = elements[e];
    if (!el.schema || !el.schema->observes || el.nodes().size() != 1 ||
        el.nodes()[0] != s.node_index)
      continue;
    if (found >= 0) return s.sensor; // two sensors on the node: the data say which, or none
    found = static_cast<int>(e);
  }
  return found;
}

/// The row of an affine observation of series s at the unknowns x0 (exact: a reading is affine).
void observe(Network& net, MeasuredSeries s, const std::vector<double>& x0, Observation& o) {
  s.sensor = reading_sensor(net, s);
  const auto n = x0.size();
  std::vector<double> x = x0, all(net.spec().nodes.size());
  const auto value = [&] {
    net.expand(0.0, x.data(), all.data());
    return simulated_value(net, s, 0.0, x.data(), all.data());
  };
  const double h0 = value();
  o.H = Eigen::RowVectorXd::Zero(static_cast<Eigen::Index>(n));
  for (std::size_t j = 0; j < n; ++j) {
    x[j] = x0[j] + 1.0;
    o.H(static_cast<Eigen::Index>(j)) = value() - h0;
    x[j] = x0[j];
  }
  double hx = 0.0;
  for (std::size_t j = 0; j < n; ++j)
    hx += o.H(static_cast<Eigen::Index>(j)) * x0[j];
  o.offset = h0 - hx;
}

} // namespace prediction_detail

namespace {

using prediction_detail::Observation;

/// The discretisations of a constant system matrix, by sampling interval (a uniformly sampled
/// record needs one).
class Discretisations {
public:
  Discretisations(const Eigen::MatrixXd& A, const Eigen::MatrixXd& Qc) : A_(A), Qc_(Qc) {}
  const Discretised& over(double h) {
    for (const auto& [step, d] : cache_)
      if (std::abs(step - h) <= 1e-9 * h) return d;
    if (cache_.size() >= 16) cache_.erase(cache_.begin());
    cache_.emplace_back(h, discretise(A_, Qc_, h));
    return cache_.back().second;
  }

private:
  Eigen::MatrixXd A_, Qc_;
  std::vector<std::pair<double, Discretised>> cache_;
};

} // namespace

/// A case's network at structural values x: its unknowns' noise slots, start, readings and, for an
/// affine network, the system matrix and the deterministic trajectory at the sample times.
struct PredictionProblem::CaseSetup {
  std::size_t c = 0;
  std::vector<double> x;
  std::unique_ptr<Network> net;          // null once cached (an affine case needs it no more)
  std::unique_ptr<NetworkStateSpace> ss; // over *net
  int m = 0;                             // filter states
  std::vector<std::size_t> process;      // node unknown i -> its sigma_w among process_nodes_
  Eigen::VectorXd x0;                    // start of the states
  std::vector<Observation> obs;          // the readings filtered (their noise is in theta)
  bool affine = false, local_linear = false;
  Eigen::MatrixXd A; // affine: the constant system matrix
  Eigen::MatrixXd Z; // affine: the deterministic states, a column a sample
};

/// The most recent affine setups (a few gradients' worth), searched by case and structural values.
struct PredictionProblem::SetupCache {
  std::mutex mutex;
  std::deque<std::shared_ptr<const CaseSetup>> entries;
  static constexpr std::size_t kCapacity = 8;
};

std::shared_ptr<PredictionProblem::SetupCache> PredictionProblem::make_cache() {
  return std::make_shared<SetupCache>();
}

std::shared_ptr<PredictionProblem::CaseSetup>
PredictionProblem::setup(std::size_t c, const std::vector<double>& x) const {
  auto s = std::make_shared<CaseSetup>();
  s->c = c;
  s->x = x;
  s->net = std::make_unique<Network>(make_(c, x));
  Network& net = *s->net;
  s->ss = std::make_unique<NetworkStateSpace>(net);
  const std::vector<int> unknown = unknown_of_spec(net);
  const MeasuredData& data = data_[c];
  s->m = s->ss->size();
  for (int i = 0; i < net.temperature_count(); ++i) {
    const auto it = std::find(process_nodes_.begin(), process_nodes_.end(), net.unknown_name(i));
    if (it == process_nodes_.end())
      throw std::invalid_argument(fmt::format("case '{}' has node '{}' that its first case lacks",
                                              cases_[c], net.unknown_name(i)));
    s->process.push_back(static_cast<std::size_t>(it - process_nodes_.begin()));
  }
  const std::vector<double> T0 = start_state(net, settings_.solver);
  for (std::size_t k = 0; k < data.series.size(); ++k) {
    const auto& ser = data.series[k];
    const auto it = std::find(measured_nodes_.begin(), measured_nodes_.end(), ser.node);
    if (it == measured_nodes_.end()) continue;
    if (unknown[static_cast<std::size_t>(ser.node_index)] < 0) continue;
    Observation o;
    o.series = k;
    o.node = static_cast<std::size_t>(it - measured_nodes_.begin());
    prediction_detail::observe(net, ser, T0, o);
    s->obs.push_back(std::move(o));
  }
  s->x0.resize(s->m);
  for (int i = 0; i < s->m; ++i)
    s->x0(i) = T0[static_cast<std::size_t>(i)];
  s->affine = net.affine();
  s->local_linear =
      settings_.local_linearisation && !s->affine && net.event_count() == 0 && s->m == net.size();
  if (!s->affine) return s;
  // An affine network (linear, time-invariant couplings) is x' = A x + b(t): the mean of every
  // prediction step follows the deterministic trajectory z, x(k+1|k) = z(k+1) + Phi (x(k|k) -
  // z(k)), so that one integration of the whole case replaces one per sample, and Phi and Qd of
  // a sampling interval are computed once.
  if (!data.times.empty()) {
    SolverOptions exact = settings_.solver;
    exact.exact_linear_max = 64;
    // Matrix exponentials, not modes: the selection's fits of a mass on the SciPy building
    // (tests/diagnose_real/building.py) end in a lower maximum of the likelihood with the modes'
    // rounding (log-likelihood 2812 instead of 2935): its optimiser is that fragile (a limit
    // docs/diagnose.md states).
    exact.exact_modes = false;
    s->Z.resize(s->m, static_cast<Eigen::Index>(data.times.size()));
    std::vector<double> T = T0;
    Eigen::Index k = 0;
    for (; k < s->Z.cols() && data.times[static_cast<std::size_t>(k)] <= 0.0; ++k)
      s->Z.col(k) = s->x0;
    if (k < s->Z.cols())
      integrate(
          net, T, 0.0, data.times.back(),
          std::vector<double>(data.times.begin() + static_cast<long>(k), data.times.end()),
          [&](double, const std::vector<double>& X) {
            if (k < s->Z.cols()) s->Z.col(k) = Eigen::Map<const Eigen::VectorXd>(X.data(), s->m);
            ++k;
          },
          exact);
    if (k != s->Z.cols())
      throw std::runtime_error("the deterministic trajectory misses sample times");
  }
  s->A = s->ss->system_matrix(0.0, s->x0);
  return s;
}

CaseInnovations PredictionProblem::filter_case(std::size_t c, const std::vector<double>& theta,
                                               bool series) const {
  if (theta.size() != params_.size())
    throw std::invalid_argument(fmt::format("{} values for the prediction problem's {} params",
                                            theta.size(), params_.size()));
  const std::vector<double> x(theta.begin(), theta.begin() + static_cast<long>(structural_));
  // An affine case's setup at these structural values may be cached (a gradient's evaluations
  // that move a noise param only); another network is set up afresh (its filter integrates it).
  std::shared_ptr<const CaseSetup> fixed;
  std::shared_ptr<CaseSetup> own;
  {
    const std::lock_guard<std::mutex> lock(cache_->mutex);
    for (const auto& e : cache_->entries)
      if (e->c == c && e->x == x) fixed = e;
  }
  if (!fixed) {
    own = setup(c, x);
    if (own->affine) {
      own->ss.reset();
      own->net.reset();
      fixed = own;
      const std::lock_guard<std::mutex> lock(cache_->mutex);
      cache_->entries.push_back(fixed);
      if (cache_->entries.size() > SetupCache::kCapacity) cache_->entries.pop_front();
    }
  }
  const CaseSetup& s = fixed ? *fixed : *own;
  const MeasuredData& data = data_[c];
  CaseInnovations out;
  out.case_name = cases_[c];
  out.times = data.times;
  const int m = s.m;
  Eigen::MatrixXd Qc = Eigen::MatrixXd::Zero(m, m);
  for (std::size_t i = 0; i < s.process.size(); ++i) {
    const double sw = theta[structural_ + s.process[i]];
    Qc(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) = sw * sw;
  }
  // The readings as set up (read in place: each holds a heap row), their variances from theta.
  const std::vector<Observation>& obs = s.obs;
  std::vector<double> variance;
  variance.reserve(obs.size());
  for (const auto& o : obs) {
    const double sv = theta[structural_ + process_nodes_.size() + o.node];
    variance.push_back(sv * sv);
    const auto& ser = data.series[o.series];
    out.nodes.push_back(ser.node);
    if (!series) continue;
    out.measured.push_back(ser.values);
    out.predicted.emplace_back(data.times.size(), kNaN);
    out.sd.emplace_back(data.times.size(), kNaN);
  }
  if (!series) out.times.clear();
  const double sd0 = settings_.initial_sd;
  KalmanFilter filter(s.x0, Eigen::MatrixXd::Identity(m, m) * (sd0 * sd0));
  // Otherwise each step integrates the network from the filtered mean (an extended Kalman
  // filter); a nonlinear network without events (radiation, temperature-dependent links) is
  // linearised at the filtered mean for each step (local linearisation, as CTSM-R does): no
  // integrator restarts.
  std::optional<Discretisations> disc;
  if (s.affine) disc.emplace(s.A, Qc);
  double t = 0.0;
  Eigen::Index prev = -1; // the sample the filter stands at (-1: the start)
  std::vector<std::size_t> which;
  for (std::size_t k = 0; k < data.times.size(); ++k) {
    if (data.times[k] > t) {
      if (s.affine) {
        const auto at = static_cast<Eigen::Index>(k);
        if (prev < 0)
          filter.predict_about(disc->over(data.times[k] - t), s.x0, s.Z.col(at));
        else
          filter.predict_about(disc->over(data.times[k] - t), s.Z.col(prev), s.Z.col(at));
      } else if (s.local_linear) {
        Eigen::MatrixXd A;
        filter.x() = local_linear_step(*own->net, filter.x(), t, data.times[k], A);
        filter.predict_covariance(discretise(A, Qc, data.times[k] - t));
      } else {
        own->ss->predict(filter, t, data.times[k], Qc, settings_.solver);
      }
    }
    t = data.times[k];
    prev = static_cast<Eigen::Index>(k);
    which.clear();
    for (std::size_t o = 0; o < obs.size(); ++o)
      if (!std::isnan(data.series[obs[o].series].values[k])) which.push_back(o);
    if (which.empty()) continue;
    if (which.size() == 1) { // one reading: the update without allocations
      const std::size_t o = which.front();
      const Observation& ob = obs[o];
      double predicted = 0.0, S = 0.0;
      out.log_likelihood += filter.update_scalar(ob.H, ob.offset, data.series[ob.series].values[k],
                                                 variance[o], predicted, S);
      if (series) {
        out.predicted[o][k] = predicted;
        out.sd[o][k] = std::sqrt(S);
      }
      ++out.points;
      continue;
    }
    const auto p = static_cast<Eigen::Index>(which.size());
    Eigen::MatrixXd H(p, m);
    Eigen::VectorXd y(p), var(p), offset(p);
    for (Eigen::Index r = 0; r < p; ++r) {
      const std::size_t w = which[static_cast<std::size_t>(r)];
      const Observation& o = obs[w];
      H.row(r) = o.H;
      offset(r) = o.offset;
      y(r) = data.series[o.series].values[k];
      var(r) = variance[w];
    }
    const Innovation in = filter.update(H, offset, y, var);
    for (Eigen::Index r = 0; series && r < p; ++r) {
      const std::size_t o = which[static_cast<std::size_t>(r)];
      out.predicted[o][k] = in.predicted(r);
      out.sd[o][k] = std::sqrt(in.S(r, r));
    }
    out.log_likelihood += in.log_likelihood;
    out.points += static_cast<std::size_t>(p);
  }
  return out;
}

double PredictionProblem::log_likelihood(const std::vector<double>& theta) const {
  double ll = 0.0;
  try {
    for (std::size_t c = 0; c < cases_.size(); ++c)
      ll += filter_case(c, theta, false).log_likelihood;
  } catch (const std::exception&) {
    return -std::numeric_limits<double>::infinity();
  }
  return std::isfinite(ll) ? ll : -std::numeric_limits<double>::infinity();
}

std::vector<CaseInnovations>
PredictionProblem::innovations(const std::vector<double>& theta) const {
  std::vector<CaseInnovations> out;
  for (std::size_t c = 0; c < cases_.size(); ++c)
    out.push_back(filter_case(c, theta, true));
  return out;
}

PredictionFit fit_prediction(const PredictionProblem& problem, std::vector<double> start,
                             bool std_errors, bool deterministic_stage) {
  if (start.empty()) start = problem.start();
  const auto boxes = problem.boxes();
  const ScalarObjective f = [&problem](const std::vector<double>& th) {
    return -problem.log_likelihood(th);
  };
  QuasiNewtonOptions qo;
  qo.threads = problem.settings().threads;
  qo.max_iterations = problem.settings().max_iterations;
  qo.ftol = problem.settings().ftol;
  std::size_t stage_evaluations = 0;
  if (deterministic_stage && problem.structural() > 0) {
    // Stage 1, the deterministic fit: the structural params and the measurement noise with
    // (nearly) no process noise, so that the filter is the simulation and its prediction errors
    // the output errors. Started with process noise, the likelihood is often higher by making the
    // noise explain a poor structure than by correcting it (a local maximum far from the
    // physical one); from the deterministic optimum the process noise only takes up what the
    // structure cannot explain.
    std::vector<std::size_t> free;
    std::vector<BoundedParam> fb;
    std::vector<double> full = start, fs;
    for (std::size_t j = 0; j < boxes.size(); ++j) {
      const auto& name = problem.params()[j].name;
      if (name.rfind("sigma_w[", 0) == 0) {
        full[j] = std::max(boxes[j].lo, 1e-3 * start[j]);
      } else {
        free.push_back(j);
        fb.push_back(boxes[j]);
        fs.push_back(start[j]);
      }
    }
    const ScalarObjective g = [&](const std::vector<double>& y) {
      std::vector<double> th = full;
      for (std::size_t k = 0; k < free.size(); ++k)
        th[free[k]] = y[k];
      return f(th);
    };
    const QuasiNewtonResult r1 = minimise_bounded(g, fb, fs, qo);
    stage_evaluations = r1.evaluations;
    if (r1.ok && r1.f <= f(start))
      for (std::size_t k = 0; k < free.size(); ++k)
        start[free[k]] = r1.x[k];
  }
  // Stage 2: everything free.
  const QuasiNewtonResult r = minimise_bounded(f, boxes, start, qo);
  PredictionFit fit;
  fit.ok = r.ok;
  fit.theta = r.x;
  fit.log_likelihood = -r.f;
  fit.iterations = r.iterations;
  fit.evaluations = r.evaluations + stage_evaluations;
  fit.converged = r.converged;
  fit.parameters = boxes.size();
  fit.points = problem.points();
  const double k = static_cast<double>(fit.parameters);
  fit.aic = -2 * fit.log_likelihood + 2 * k;
  fit.bic = -2 * fit.log_likelihood + k * std::log(static_cast<double>(fit.points));
  const std::size_t n = boxes.size();
  fit.std_errors.assign(n, kNaN);
  if (!fit.ok) return fit;
  if (!fit.converged)
    fit.notes.push_back(
        fmt::format("the likelihood's maximum was not reached in {} iterations", fit.iterations));
  const WorkingCoordinates wc(boxes);
  const Eigen::VectorXd u = wc.to_u(fit.theta);
  for (std::size_t j = 0; j < n; ++j)
    if (u(static_cast<Eigen::Index>(j)) < 1e-6 || u(static_cast<Eigen::Index>(j)) > 1 - 1e-6)
      fit.notes.push_back(
          fmt::format("{} ends on its bound ({:.4g})", problem.params()[j].name, fit.theta[j]));
  if (std_errors) add_standard_errors(problem, fit);
  return fit;
}

void add_standard_errors(const PredictionProblem& problem, PredictionFit& fit) {
  const auto boxes = problem.boxes();
  const std::size_t n = boxes.size();
  fit.std_errors.assign(n, kNaN);
  if (!fit.ok || n == 0) return;
  const ScalarObjective f = [&problem](const std::vector<double>& th) {
    return -problem.log_likelihood(th);
  };
  const WorkingCoordinates wc(boxes);
  const Eigen::VectorXd u = wc.to_u(fit.theta);
  const Eigen::MatrixXd H = scaled_hessian(f, boxes, fit.theta, 1e-4, problem.settings().threads);
  fit.evaluations += 2 * n * n + 1;
  // Parameters on a bound or without curvature (a noise intensity the data cannot see) have no
  // standard error; the others' come from the inverse Hessian of their block.
  std::vector<Eigen::Index> free;
  for (std::size_t j = 0; j < n; ++j) {
    const auto a = static_cast<Eigen::Index>(j);
    if (u(a) > 1e-6 && u(a) < 1 - 1e-6 && std::isfinite(H(a, a)) && H(a, a) > 0) free.push_back(a);
  }
  const auto m = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd Hf(m, m);
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = 0; j < m; ++j)
      Hf(i, j) = H(free[i], free[j]);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(Hf);
  if (m == 0 || !Hf.allFinite() || ldlt.info() != Eigen::Success ||
      (ldlt.vectorD().array() <= 0).any()) {
    fit.notes.push_back("the likelihood's Hessian is not positive definite: no standard errors "
                        "(params the data cannot tell apart)");
    return;
  }
  if (m < static_cast<Eigen::Index>(n))
    fit.notes.push_back(fmt::format("{} of {} parameters (on a bound, or without effect on the "
                                    "likelihood) have no standard error",
                                    n - static_cast<std::size_t>(m), n));
  const Eigen::MatrixXd cov = ldlt.solve(Eigen::MatrixXd::Identity(m, m));
  fit.correlation.assign(n, std::vector<double>(n, kNaN));
  for (Eigen::Index i = 0; i < m; ++i) {
    const auto pi = static_cast<std::size_t>(free[i]);
    const double sy = std::sqrt(std::max(0.0, cov(i, i)));
    fit.std_errors[pi] = boxes[pi].scale == ParamScale::log ? fit.theta[pi] * sy : sy;
    for (Eigen::Index j = 0; j < m; ++j)
      fit.correlation[pi][static_cast<std::size_t>(free[j])] =
          cov(i, j) / std::sqrt(cov(i, i) * cov(j, j));
  }
}

double chi_square_upper(double x, int df) {
  if (df <= 0) return x > 0 ? 0.0 : 1.0;
  return gamma_q(0.5 * df, 0.5 * x);
}

LikelihoodRatio likelihood_ratio(double ll_small, std::size_t k_small, double ll_large,
                                 std::size_t k_large) {
  LikelihoodRatio r;
  r.statistic = 2.0 * (ll_large - ll_small);
  r.df = static_cast<int>(k_large) - static_cast<int>(k_small);
  r.p_value = chi_square_upper(std::max(0.0, r.statistic), std::max(1, r.df));
  return r;
}

} // namespace thermnet
