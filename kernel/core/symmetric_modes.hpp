#pragma once
/// The modes of a reciprocal network (A = C^-1 J with J symmetric): its exact steps over any
/// interval from one symmetric eigendecomposition instead of one matrix exponential each.

#include "kernel/core/exact_linear.hpp"

#include <Eigen/Dense>

#include <optional>

namespace thermnet {

/// A = D^-1 Q diag(lambda) Q^T D with D = diag(sqrt(C)) and Q orthogonal.
class SymmetricModes {
public:
  /// The modes of A, or nothing when C A is not symmetric (to 1e-10 of its largest entry: a
  /// sensor's lag, an advective link) or a capacity is not positive.
  static std::optional<SymmetricModes> of(const Eigen::MatrixXd& A, const Eigen::VectorXd& C);
  /// Phi, Psi0 and Psi1 of A over h (as linear_step(A, h) computes them).
  LinearStep step(double h) const;

private:
  Eigen::VectorXd lambda_; // eigenvalues, 1/s
  Eigen::MatrixXd V_;      // D^-1 Q
  Eigen::MatrixXd W_;      // Q^T D = V^-1
};

} // namespace thermnet
