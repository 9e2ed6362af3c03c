#pragma once
/// The linear algebra of a continuous-discrete Kalman filter: exact discretisation of a linear
/// stochastic differential equation over a sampling interval (Van Loan), the covariance
/// prediction, and the measurement update with its innovation and log-likelihood. The mean's
/// propagation belongs to the model (network_state_space.hpp integrates the network itself).

#include <Eigen/Dense>

#include <vector>

namespace thermnet {

/// dx = A x dt + dw with E[dw dw'] = Qc dt, over an interval h: x(h) = Phi x(0) + w, Cov(w) = Qd.
struct Discretised {
  Eigen::MatrixXd Phi; ///< transition matrix exp(A h)
  Eigen::MatrixXd Qd;  ///< process-noise covariance int_0^h exp(A s) Qc exp(A' s) ds
};

/// Phi and Qd of (A, Qc) over h by one matrix exponential of the Van Loan block matrix.
Discretised discretise(const Eigen::MatrixXd& A, const Eigen::MatrixXd& Qc, double h);

/// What a measurement update saw: the one-step-ahead prediction of the measured states, the
/// innovation (measured minus predicted) and its covariance.
struct Innovation {
  Eigen::VectorXd predicted;  ///< H x(k|k-1)
  Eigen::VectorXd innovation; ///< y - H x(k|k-1)
  Eigen::MatrixXd S;          ///< H P(k|k-1) H' + R
  double log_likelihood = 0;  ///< log N(innovation; 0, S), 2 pi included
};

/// A Gaussian state estimate (mean x, covariance P) updated by measurements of single states.
class KalmanFilter {
public:
  /// Starts from the prior N(x0, P0).
  KalmanFilter(Eigen::VectorXd x0, Eigen::MatrixXd P0) : x_(std::move(x0)), P_(std::move(P0)) {}
  /// The mean.
  Eigen::VectorXd& x() { return x_; }
  /// The mean (read only).
  const Eigen::VectorXd& x() const { return x_; }
  /// The covariance.
  const Eigen::MatrixXd& P() const { return P_; }
  /// Sets the covariance (a smoother or a restart).
  void set_P(Eigen::MatrixXd P) { P_ = std::move(P); }
  /// P <- Phi P Phi' + Qd (the mean is propagated by the model).
  void predict_covariance(const Discretised& d);
  /// Updates with measurements y of the states `states` (each observed directly) with variances
  /// `variance`; Joseph form. Returns the innovation seen (empty when no state is measured).
  Innovation update(const std::vector<int>& states, const Eigen::VectorXd& y,
                    const Eigen::VectorXd& variance);
  /// Updates with affine measurements y = H x + offset (a sensor's reading through its lag,
  /// offset and gain) with variances `variance`; Joseph form.
  Innovation update(const Eigen::MatrixXd& H, const Eigen::VectorXd& offset,
                    const Eigen::VectorXd& y, const Eigen::VectorXd& variance);
  /// One affine measurement y = h x + offset with variance `variance` (Joseph form), without
  /// allocating: returns the log-likelihood, the prediction h x + offset and its variance S.
  double update_scalar(const Eigen::RowVectorXd& h, double offset, double y, double variance,
                       double& predicted, double& S);
  /// x <- z1 + Phi (x - z0) and P <- Phi P Phi' + Qd without allocating (an affine model's step
  /// about its deterministic trajectory z).
  void predict_about(const Discretised& d, const Eigen::Ref<const Eigen::VectorXd>& z0,
                     const Eigen::Ref<const Eigen::VectorXd>& z1);

private:
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  Eigen::VectorXd v_, w_; // workspace of the allocation-free steps
  Eigen::MatrixXd M_;
};

} // namespace thermnet
