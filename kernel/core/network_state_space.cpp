// NetworkStateSpace: the network's prediction step of a continuous-discrete (extended) Kalman
// filter: mean by the integrator, covariance by the exact discretisation of the linearisation.

#include "kernel/core/network_state_space.hpp"

#include "kernel/core/integrator.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace thermnet {

/// The network with an extra heat flow q into one unknown (the input state's dynamics).
class NetworkStateSpace::Driven final : public ForwardingSystem {
public:
  Driven(Network& net, int input_unknown) : ForwardingSystem(net), input_(input_unknown) {}
  double q = 0.0; ///< extra heat flow, W

  void heat_balance(double t, const double* T, double* F) override {
    ForwardingSystem::heat_balance(t, T, F);
    if (input_ >= 0) F[input_] += q;
  }

private:
  int input_;
};

NetworkStateSpace::NetworkStateSpace(Network& net, int input_unknown)
    : net_(net), n_(net.size()), input_(input_unknown) {
  const auto& C = net_.capacities();
  for (int i = 0; i < n_; ++i)
    if (!(C[static_cast<std::size_t>(i)] > 0.0))
      throw std::invalid_argument(fmt::format(
          "node '{}' has no heat capacity; arithmetic nodes are not supported by the Kalman filter",
          net_.unknown_name(i)));
  if (input_ >= n_) throw std::invalid_argument("the input state names no unknown of the network");
  m_ = n_ + (input_ >= 0 ? 1 : 0);
  driven_ = std::make_unique<Driven>(net_, input_);
}

NetworkStateSpace::~NetworkStateSpace() = default;

Eigen::MatrixXd NetworkStateSpace::system_matrix(double t, const Eigen::VectorXd& x) {
  const auto& pat = net_.jacobian_pattern();
  const auto& C = net_.capacities();
  jac_.resize(static_cast<std::size_t>(pat.nnz()));
  net_.jacobian(t, x.data(), jac_.data());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m_, m_);
  for (int i = 0; i < n_; ++i)
    for (int k = pat.row_ptr[i]; k < pat.row_ptr[i + 1]; ++k)
      A(i, pat.col_idx[k]) = jac_[static_cast<std::size_t>(k)] / C[static_cast<std::size_t>(i)];
  if (input_ >= 0) A(input_, n_) = 1.0 / C[static_cast<std::size_t>(input_)];
  return A;
}

Discretised NetworkStateSpace::predict(KalmanFilter& filter, double t0, double t1,
                                       const Eigen::MatrixXd& Qc, const SolverOptions& solver) {
  Eigen::VectorXd& x = filter.x();
  Discretised d = discretise(system_matrix(t0, x), Qc, t1 - t0);
  T_.assign(x.data(), x.data() + n_);
  driven_->q = input_ >= 0 ? x(n_) : 0.0;
  integrate(*driven_, T_, t0, t1, {}, nullptr, solver);
  for (int i = 0; i < n_; ++i)
    x(i) = T_[static_cast<std::size_t>(i)];
  filter.predict_covariance(d);
  return d;
}

} // namespace thermnet
