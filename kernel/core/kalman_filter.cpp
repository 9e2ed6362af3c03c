// The continuous-discrete Kalman filter's linear algebra: Van Loan's discretisation, covariance
// prediction, Joseph-form update with the innovation's log-likelihood.

#include "kernel/core/kalman_filter.hpp"

#include <unsupported/Eigen/MatrixFunctions>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace thermnet {

Discretised discretise(const Eigen::MatrixXd& A, const Eigen::MatrixXd& Qc, double h) {
  const Eigen::Index m = A.rows();
  // Van Loan (1978): exp([[-A, Qc], [0, A']] h) = [[., Phi^-1 Qd], [0, Phi']].
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * m, 2 * m);
  M.topLeftCorner(m, m) = -A * h;
  M.topRightCorner(m, m) = Qc * h;
  M.bottomRightCorner(m, m) = A.transpose() * h;
  const Eigen::MatrixXd E = M.exp();
  Discretised d;
  d.Phi = E.bottomRightCorner(m, m).transpose();
  d.Qd = d.Phi * E.topRightCorner(m, m);
  d.Qd = 0.5 * (d.Qd + d.Qd.transpose());
  return d;
}

void KalmanFilter::predict_covariance(const Discretised& d) {
  P_ = d.Phi * P_ * d.Phi.transpose() + d.Qd;
  P_ = 0.5 * (P_ + P_.transpose());
}

Innovation KalmanFilter::update(const std::vector<int>& states, const Eigen::VectorXd& y,
                                const Eigen::VectorXd& variance) {
  const auto p = static_cast<Eigen::Index>(states.size());
  const Eigen::Index m = x_.size();
  if (y.size() != p || variance.size() != p)
    throw std::invalid_argument("a Kalman update needs one value and one variance per state");
  if (p == 0) return {};
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(p, m);
  for (Eigen::Index r = 0; r < p; ++r)
    H(r, states[static_cast<std::size_t>(r)]) = 1.0;
  return update(H, Eigen::VectorXd::Zero(p), y, variance);
}

Innovation KalmanFilter::update(const Eigen::MatrixXd& H, const Eigen::VectorXd& offset,
                                const Eigen::VectorXd& y, const Eigen::VectorXd& variance) {
  const Eigen::Index p = H.rows(), m = x_.size();
  if (y.size() != p || variance.size() != p || offset.size() != p || H.cols() != m)
    throw std::invalid_argument("a Kalman update needs one row, value and variance per "
                                "measurement");
  Innovation in;
  if (p == 0) return in;
  in.predicted = H * x_ + offset;
  in.innovation = y - in.predicted;
  in.S = H * P_ * H.transpose();
  in.S.diagonal() += variance;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(in.S);
  const Eigen::MatrixXd K = ldlt.solve(H * P_).transpose();
  const double log_det = ldlt.vectorD().array().log().sum();
  const double quad = in.innovation.dot(ldlt.solve(in.innovation));
  in.log_likelihood =
      -0.5 * (static_cast<double>(p) * std::log(2.0 * std::numbers::pi) + log_det + quad);
  x_ += K * in.innovation;
  const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(m, m) - K * H;
  P_ = IKH * P_ * IKH.transpose() + K * variance.asDiagonal() * K.transpose();
  P_ = 0.5 * (P_ + P_.transpose());
  return in;
}

double KalmanFilter::update_scalar(const Eigen::RowVectorXd& h, double offset, double y,
                                   double variance, double& predicted, double& S) {
  const Eigen::Index m = x_.size();
  if (h.size() != m) throw std::invalid_argument("a Kalman update needs one row per measurement");
  v_.resize(m); // P h'
  v_.noalias() = P_.lazyProduct(h.transpose());
  predicted = h.dot(x_) + offset;
  S = h.dot(v_) + variance;
  const double innovation = y - predicted;
  if (!(S > 0.0)) return -std::numeric_limits<double>::infinity();
  w_.resize(m); // the gain K = P h' / S
  w_ = v_ / S;
  x_ += w_ * innovation;
  // Joseph form (I - K h) P (I - K h)' + K r K' = P - K (P h')' - (P h') K' + S K K'.
  P_.noalias() -= w_ * v_.transpose();
  P_.noalias() -= v_ * w_.transpose();
  P_.noalias() += (S * w_) * w_.transpose();
  M_ = P_.transpose();
  P_ = 0.5 * (P_ + M_);
  return -0.5 * (std::log(2.0 * std::numbers::pi) + std::log(S) + innovation * innovation / S);
}

void KalmanFilter::predict_about(const Discretised& d, const Eigen::Ref<const Eigen::VectorXd>& z0,
                                 const Eigen::Ref<const Eigen::VectorXd>& z1) {
  v_ = x_ - z0;
  x_.noalias() = d.Phi.lazyProduct(v_);
  x_ += z1;
  M_.noalias() = d.Phi.lazyProduct(P_);
  P_.noalias() = M_.lazyProduct(d.Phi.transpose());
  P_ += d.Qd;
  M_ = P_.transpose();
  P_ = 0.5 * (P_ + M_);
}

} // namespace thermnet
