#pragma once
/// A thermal network as a continuous-discrete stochastic state-space model, the form of CTSM-R
/// and pySIP: C dT/dt = F(t, T) (+ e q, an optional extra heat input q into one node, itself a
/// random walk) plus process noise, observed at discrete times. Between two samples the mean is
/// propagated by the network's own integrator (nonlinear elements, time-varying inputs and
/// thermostat events exact to the solver tolerance) and the covariance by the network linearised
/// at the mean with its analytic Jacobian, discretised exactly (an extended Kalman filter; exact
/// for a linear network). Used by `thermnet estimate` (ekf) and the prediction-error criterion.

#include "kernel/core/kalman_filter.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/solver_types.hpp"

#include <Eigen/Dense>

#include <memory>
#include <vector>

namespace thermnet {

/// The network's unknowns (node temperatures, element states), and optionally an extra heat
/// input q into one unknown node, as the state of a Kalman filter.
class NetworkStateSpace {
public:
  /// Over `net` (kept by reference); `input_unknown` >= 0 adds the input state q (W) into that
  /// unknown. Throws std::invalid_argument naming a node without heat capacity (an arithmetic
  /// node has no dynamics to filter).
  explicit NetworkStateSpace(Network& net, int input_unknown = -1);
  ~NetworkStateSpace();
  NetworkStateSpace(const NetworkStateSpace&) = delete;
  NetworkStateSpace& operator=(const NetworkStateSpace&) = delete;

  /// States: the network's unknowns, then q when there is an input.
  int size() const { return m_; }
  /// The network's unknowns (node temperatures first, then element states).
  int unknowns() const { return n_; }
  /// The state index of q (-1 without an input).
  int input_state() const { return input_ >= 0 ? n_ : -1; }
  /// Continuous-time system matrix at (t, x): C^-1 dF/dT, and 1/C in q's column.
  Eigen::MatrixXd system_matrix(double t, const Eigen::VectorXd& x);
  /// One prediction step of `filter` from t0 to t1 with continuous process-noise intensity Qc
  /// (per second): the mean by the integrator, the covariance by the linearisation at (t0, x(t0)).
  /// Returns the discretisation used (the smoother needs its transition matrix). Throws
  /// SolverError when the integrator fails.
  Discretised predict(KalmanFilter& filter, double t0, double t1, const Eigen::MatrixXd& Qc,
                      const SolverOptions& solver);

private:
  class Driven;
  Network& net_;
  std::unique_ptr<Driven> driven_;
  int n_ = 0, m_ = 0, input_ = -1;
  std::vector<double> jac_, T_;
};

} // namespace thermnet
