#pragma once
/// The exact solution of a linear network between its breakpoints: C dT/dt = J T + f(t) with J
/// constant and f linear between breakpoints (linear time-invariant couplings, prescribed inputs
/// from constants, steps, pwl and tables) is T(t + h) = Phi T(t) + Psi0 g(t) + Psi1 (g(t + h) -
/// g(t)) with g = C^-1 f, Phi = exp(A h), A = C^-1 J, Psi0 = int_0^h exp(A s) ds and Psi1 = int_0^h
/// exp(A (h - s)) s / h ds, all three read off one matrix exponential (Van Loan's block form). It
/// is the discretisation the prediction-error criterion's Kalman filter uses, exact whatever the
/// step, so a building's 1,700 samples of tabulated weather need 1,700 matrix-vector products
/// instead of 1,700 restarts of a BDF integrator. integrate() uses it where SolverOptions allows.

#include "kernel/core/integrator.hpp"
#include "kernel/core/thermal_system.hpp"

#include <Eigen/Dense>

#include <vector>

namespace thermnet {

/// The exact discretisation of x' = A x + g(s) over one interval of length h, g linear in s.
struct LinearStep {
  double h = 0.0;       ///< interval length, s
  Eigen::MatrixXd Phi;  ///< exp(A h)
  Eigen::MatrixXd Psi0; ///< int_0^h exp(A s) ds
  Eigen::MatrixXd Psi1; ///< int_0^h exp(A (h - s)) s / h ds
};

/// Phi, Psi0 and Psi1 of A over h, from one matrix exponential of Van Loan's block form: x(h) =
/// Phi x(0) + Psi0 g(0) + Psi1 (g(h) - g(0)).
LinearStep linear_step(const Eigen::MatrixXd& A, double h);

/// One step of the local linearisation (Ozaki's scheme, the one CTSM-R's extended Kalman filter
/// uses for a nonlinear model): the network linearised at (t0, x), its heat flows at x read at a
/// third and two thirds of the step, the linearised system integrated exactly to t1. Returns the
/// state at t1 and sets `A` to the system matrix C^-1 dF/dT at (t0, x). Exact for a linear network
/// whose inputs are linear over [t0, t1]; throws SolverError when the result is not finite.
Eigen::VectorXd local_linear_step(ThermalSystem& sys, const Eigen::VectorXd& x, double t0,
                                  double t1, Eigen::MatrixXd& A);

/// Integrates a piecewise-affine system (ThermalSystem::piecewise_affine()) exactly from t0 to t1:
/// T holds the initial state on entry and the final state on exit; `out` is called at every time
/// of `output_times` within [t0, t1]. Throws std::invalid_argument when the system is not
/// piecewise affine or has an algebraic node. With `modes`, a reciprocal network's steps come from
/// its eigenmodes (SolverOptions::exact_modes).
SolverStats integrate_exact(ThermalSystem& sys, std::vector<double>& T, double t0, double t1,
                            const std::vector<double>& output_times, const OutputCallback& out,
                            bool modes = true);

} // namespace thermnet
