// integrate_exact(): a linear network stepped from breakpoint to breakpoint (and output time) by
// its exact discretisation, one matrix exponential per distinct interval length and system matrix
// (a network whose couplings switch at breakpoints has one matrix per state of its switches).

#include "kernel/core/exact_linear.hpp"

#include "kernel/core/absolute_zero.hpp"
#include "kernel/core/sorted_runs.hpp"
#include "kernel/core/symmetric_modes.hpp"
#include "kernel/core/system_evaluator.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

namespace thermnet {
namespace {

/// The steps of A over the interval lengths met (a uniformly sampled record needs one or two; a
/// record with jittered sample times one per sample): through its modes when the network is
/// reciprocal (SymmetricModes: two small products a step), else by matrix exponentials.
class Steps {
public:
  /// The steps of A = C^-1 J, through its modes when `modes` and it has them.
  Steps(Eigen::MatrixXd A, const Eigen::VectorXd& C, bool modes)
      : A_(std::move(A)), modes_(modes ? SymmetricModes::of(A_, C) : std::nullopt) {}
  const LinearStep& over(double h) {
    for (const LinearStep& s : cache_)
      if (std::abs(s.h - h) <= 1e-12 * h) return s;
    if (cache_.size() >= 64) cache_.erase(cache_.begin());
    cache_.push_back(modes_ ? modes_->step(h) : linear_step(A_, h));
    ++computed_;
    return cache_.back();
  }
  std::size_t computed() const { return computed_; }
  const Eigen::MatrixXd& matrix() const { return A_; }

private:
  Eigen::MatrixXd A_;
  std::optional<SymmetricModes> modes_;
  std::vector<LinearStep> cache_;
  std::size_t computed_ = 0;
};

/// Writes the system matrix C^-1 J of `sys` at (t, T) into A (n x n, dense); `jac` is scratch.
void system_matrix_into(ThermalSystem& sys, double t, const double* T, const Eigen::VectorXd& Cinv,
                        std::vector<double>& jac, Eigen::MatrixXd& A) {
  const int n = sys.size();
  const SparsityPattern& pat = sys.jacobian_pattern();
  jac.resize(static_cast<std::size_t>(pat.nnz()));
  sys.jacobian(t, T, jac.data());
  A.setZero(n, n);
  for (int i = 0; i < n; ++i)
    for (int k = pat.row_ptr[static_cast<std::size_t>(i)];
         k < pat.row_ptr[static_cast<std::size_t>(i) + 1]; ++k)
      A(i, pat.col_idx[static_cast<std::size_t>(k)]) += Cinv(i) * jac[static_cast<std::size_t>(k)];
}

/// The system matrix C^-1 J of `sys` at (t, T), dense.
Eigen::MatrixXd system_matrix(ThermalSystem& sys, double t, const double* T,
                              const Eigen::VectorXd& Cinv) {
  std::vector<double> jac;
  Eigen::MatrixXd A;
  system_matrix_into(sys, t, T, Cinv, jac, A);
  return A;
}

/// One constant system matrix of a piecewise-affine system, its steps, and A T_ref (the input is
/// g(t) = C^-1 F(t, T_ref) - A T_ref at any T_ref while A holds).
struct Piece {
  Steps steps;
  Eigen::VectorXd A_ref;
};

/// The pieces met in a run (a lid open or closed: two), found by their matrix.
class Pieces {
public:
  /// Pieces whose steps use the modes when `modes` (Steps).
  explicit Pieces(bool modes) : modes_(modes) {}
  /// The piece of matrix A, made when first met (A_ref = A ref).
  Piece& of(const Eigen::MatrixXd& A, const Eigen::VectorXd& C, const Eigen::VectorXd& ref) {
    for (auto& p : pieces_)
      if (p->steps.matrix() == A) return *p;
    if (pieces_.size() >= 16) {
      evicted_ += pieces_.front()->steps.computed();
      pieces_.erase(pieces_.begin());
    }
    pieces_.push_back(std::make_unique<Piece>(Piece{Steps(A, C, modes_), A * ref}));
    return *pieces_.back();
  }
  /// Steps computed in all pieces.
  std::size_t computed() const {
    std::size_t c = evicted_;
    for (const auto& p : pieces_)
      c += p->steps.computed();
    return c;
  }

private:
  bool modes_;
  std::vector<std::unique_ptr<Piece>> pieces_;
  std::size_t evicted_ = 0; // steps computed in pieces no longer kept
};

} // namespace

LinearStep linear_step(const Eigen::MatrixXd& A, double h) {
  // exp([[A h, I h, 0], [0, 0, I], [0, 0, 0]]) = [[Phi, Psi0, Psi1], ...]: with the input
  // g(s) = g0 + (g1 - g0) s / h over the interval, x(h) = Phi x(0) + Psi0 g0 + Psi1 (g1 - g0).
  const Eigen::Index n = A.rows();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  M.topLeftCorner(n, n) = A * h;
  M.block(0, n, n, n) = Eigen::MatrixXd::Identity(n, n) * h;
  M.block(n, 2 * n, n, n) = Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd E = M.exp();
  LinearStep s;
  s.h = h;
  s.Phi = E.topLeftCorner(n, n);
  s.Psi0 = E.block(0, n, n, n);
  s.Psi1 = E.block(0, 2 * n, n, n);
  return s;
}

Eigen::VectorXd local_linear_step(ThermalSystem& sys, const Eigen::VectorXd& x, double t0,
                                  double t1, Eigen::MatrixXd& A) {
  const int n = sys.size();
  if (x.size() != n) throw std::invalid_argument("local_linear_step: wrong size of the state");
  const std::vector<double>& C = sys.capacities();
  Eigen::VectorXd Cinv(n);
  for (int i = 0; i < n; ++i)
    Cinv(i) = 1.0 / C[static_cast<std::size_t>(i)];
  A = system_matrix(sys, t0, x.data(), Cinv);
  const double h = t1 - t0;
  if (!(h > 0.0)) return x;
  // With d = x(t) - x(t0): d' = A d + g(t), g the rates at x(t0) (the inputs linear over the step).
  std::vector<double> F(static_cast<std::size_t>(n));
  const auto g = [&](double t) {
    sys.heat_balance(t, x.data(), F.data());
    return Eigen::VectorXd(Cinv.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(F.data(), n)));
  };
  const Eigen::VectorXd ga = g(t0 + h / 3.0), gb = g(t0 + 2.0 * h / 3.0);
  const Eigen::VectorXd g0 = 2.0 * ga - gb, g1 = 2.0 * gb - ga;
  const LinearStep s = linear_step(A, h);
  Eigen::VectorXd next = x + s.Psi0 * g0 + s.Psi1 * (g1 - g0);
  if (!next.allFinite())
    throw SolverError(fmt::format("the locally linearised network is not finite at t = {:g} s", t1),
                      "local_linear_step", -1, t1, {});
  return next;
}

SolverStats integrate_exact(ThermalSystem& sys, std::vector<double>& T, double t0, double t1,
                            const std::vector<double>& output_times, const OutputCallback& out,
                            bool modes) {
  if (!sys.piecewise_affine())
    throw std::invalid_argument("integrate_exact: the system is not piecewise affine");
  const int n = sys.size();
  const auto un = static_cast<std::size_t>(n);
  if (T.size() != un) throw std::invalid_argument("integrate_exact: wrong size of the state");
  const std::vector<double>& C = sys.capacities();
  for (int i = 0; i < n; ++i)
    if (!(C[static_cast<std::size_t>(i)] > 0.0))
      throw std::invalid_argument("integrate_exact: an algebraic node has no dynamics");
  // A = C^-1 J (constant, or constant between breakpoints), and g(t) = C^-1 F(t, T_ref) - A T_ref
  // at any T_ref (F is affine while A holds).
  const Eigen::VectorXd Cv = Eigen::Map<const Eigen::VectorXd>(C.data(), n);
  const Eigen::VectorXd Cinv = Cv.cwiseInverse();
  const bool one_matrix = sys.piecewise_linear();
  const std::vector<double> ref = T;
  const Eigen::Map<const Eigen::VectorXd> ref_v(ref.data(), n);
  std::vector<double> jac;
  Eigen::MatrixXd A;
  system_matrix_into(sys, t0, T.data(), Cinv, jac, A);
  Pieces pieces(modes);
  Piece* piece = &pieces.of(A, Cv, ref_v);
  long jac_evals = 1;
  std::vector<double> F(un);
  SolverStats stats;
  stats.integrator = "exact-linear";
  stats.linear_solver = "dense";
  // g(t) into `into`, without allocating (this loop runs once per sample of a long record).
  const auto g = [&](double t, Eigen::VectorXd& into) {
    sys.heat_balance(t, ref.data(), F.data());
    ++stats.rhs_evals;
    into = Cinv.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(F.data(), n)) - piece->A_ref;
  };
  Eigen::VectorXd ga(n), gb(n), g0(n), dg(n), x_before(n);
  // The grid: t0, the breakpoints and the output times, in order.
  std::vector<double> grid = sys.breakpoints(t0, t1), run;
  for (double t : output_times)
    if (t > t0 && t <= t1) run.push_back(t);
  run.push_back(t1);
  merge_sorted_run(grid, run.begin(), run.end());
  std::size_t next_out = 0;
  while (next_out < output_times.size() && output_times[next_out] < t0)
    ++next_out;
  Eigen::Map<Eigen::VectorXd> x(T.data(), n);
  const auto emit = [&](double t) {
    while (next_out < output_times.size() && output_times[next_out] <= t) {
      out(output_times[next_out], T);
      ++next_out;
    }
  };
  if (out) emit(t0);
  double t = t0;
  for (double tn : grid) {
    const double h = tn - t;
    if (!(h > 0.0)) continue;
    if (!one_matrix) { // the matrix inside this interval (the grid holds every breakpoint)
      system_matrix_into(sys, t + 0.5 * h, ref.data(), Cinv, jac, A);
      ++jac_evals;
      piece = &pieces.of(A, Cv, ref_v);
    }
    // The input is linear inside the interval (it may jump at either end): read it at a third
    // and two thirds of the way and extended to both ends.
    g(t + h / 3.0, ga);
    g(t + 2.0 * h / 3.0, gb);
    g0 = 2.0 * ga - gb;
    dg = 3.0 * (gb - ga); // g1 - g0, with g1 = 2 gb - ga
    const LinearStep& s = piece->steps.over(h);
    x_before = x;
    x.noalias() = s.Phi.lazyProduct(x_before);
    x.noalias() += s.Psi0.lazyProduct(g0);
    x.noalias() += s.Psi1.lazyProduct(dg);
    ++stats.steps;
    if (!x.allFinite())
      throw SolverError(fmt::format("the exact solution of the linear network is not finite at "
                                    "t = {:g} s (an input or a conductance is not finite, or the "
                                    "network is unstable)",
                                    tn),
                        "integrate_exact", -1, tn, {});
    // Like every integration, a run that drives a node below 0 K fails there, naming it.
    if (const int i = detail::coldest_below_absolute_zero(T.data(), sys.temperature_count());
        i >= 0) {
      // When it crossed 0 K: bisected on the exact solution inside the interval.
      double lo = 0.0, hi = h;
      for (int k = 0; k < 60 && hi - lo > 1e-9 * h; ++k) {
        const double mid = 0.5 * (lo + hi);
        const LinearStep part = linear_step(piece->steps.matrix(), mid);
        const Eigen::VectorXd at =
            part.Phi * x_before + part.Psi0 * g0 + part.Psi1 * (dg * (mid / h));
        (at(i) < 0.0 ? hi : lo) = mid;
      }
      const detail::SystemEvaluator ev(sys);
      detail::fail_below_absolute_zero(ev,
                                       {.unknown = i,
                                        .crossing = t + hi,
                                        .kelvin = T[static_cast<std::size_t>(i)],
                                        .reached = tn,
                                        .steady = false},
                                       "integrate_exact");
    }
    t = tn;
    if (out) emit(t);
  }
  stats.jac_evals = jac_evals;
  stats.linear_setups = static_cast<long>(pieces.computed());
  return stats;
}

} // namespace thermnet
