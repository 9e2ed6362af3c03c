// SymmetricModes: exact steps of a reciprocal linear network through its eigenmodes.

#include "kernel/core/symmetric_modes.hpp"

#include <cmath>

namespace thermnet {
namespace {

/// phi1(z) = (e^z - 1) / z and phi2(z) = (e^z - 1 - z) / z^2; by their series where |z| < 0.5
/// (sum z^k / (k + 1)! and z^k / (k + 2)!, to 18 terms: below 1e-17 left), where the closed forms
/// cancel.
void phi12(double z, double& p1, double& p2) {
  if (std::abs(z) < 0.5) {
    double term1 = 1.0, term2 = 0.5; // z^k / (k + 1)!, z^k / (k + 2)!
    p1 = 0.0;
    p2 = 0.0;
    for (int k = 0; k < 18; ++k) {
      p1 += term1;
      p2 += term2;
      term1 *= z / (k + 2);
      term2 *= z / (k + 3);
    }
    return;
  }
  const double em1 = std::expm1(z);
  p1 = em1 / z;
  p2 = (em1 - z) / (z * z);
}

} // namespace

std::optional<SymmetricModes> SymmetricModes::of(const Eigen::MatrixXd& A,
                                                 const Eigen::VectorXd& C) {
  const Eigen::Index n = A.rows();
  if (A.cols() != n || C.size() != n || !(C.array() > 0.0).all() || !A.allFinite())
    return std::nullopt;
  const Eigen::MatrixXd J = C.asDiagonal() * A;
  const double largest = J.cwiseAbs().maxCoeff();
  if (((J - J.transpose()).cwiseAbs().array() > 1e-10 * largest).any()) return std::nullopt;
  const Eigen::VectorXd d = C.cwiseSqrt();
  const Eigen::VectorXd dinv = d.cwiseInverse();
  Eigen::MatrixXd S = dinv.asDiagonal() * J * dinv.asDiagonal();
  S = 0.5 * (S + S.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
  if (eig.info() != Eigen::Success) return std::nullopt;
  SymmetricModes m;
  m.lambda_ = eig.eigenvalues();
  m.V_ = dinv.asDiagonal() * eig.eigenvectors();
  m.W_ = eig.eigenvectors().transpose() * d.asDiagonal();
  return m;
}

LinearStep SymmetricModes::step(double h) const {
  const Eigen::Index n = lambda_.size();
  Eigen::VectorXd e(n), p1(n), p2(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double z = lambda_(k) * h;
    e(k) = std::exp(z);
    phi12(z, p1(k), p2(k));
  }
  LinearStep s;
  s.h = h;
  s.Phi = V_ * e.asDiagonal() * W_;
  s.Psi0 = V_ * (h * p1).asDiagonal() * W_;
  s.Psi1 = V_ * (h * p2).asDiagonal() * W_;
  return s;
}

} // namespace thermnet
