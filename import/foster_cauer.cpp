#include "import/foster_cauer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace thermnet::importer {

namespace {

using Real = long double;

/// Cells sorted by time constant, those with equal ones merged (their resistances add).
std::vector<FosterCell> merged(std::vector<FosterCell> cells) {
  for (const FosterCell& c : cells)
    if (!(c.R > 0) || !(c.C > 0) || !std::isfinite(c.R) || !std::isfinite(c.C))
      throw FosterError(
          fmt::format("a Foster cell needs positive R and C, got R = {}, C = {}", c.R, c.C));
  std::sort(cells.begin(), cells.end(),
            [](const FosterCell& a, const FosterCell& b) { return a.R * a.C < b.R * b.C; });
  std::vector<FosterCell> out;
  for (const FosterCell& c : cells) {
    const double tau = c.R * c.C;
    if (!out.empty()) {
      FosterCell& last = out.back();
      const double last_tau = last.R * last.C;
      if (std::fabs(tau - last_tau) <= 1e-12 * tau) {
        last.R += c.R;
        last.C = last_tau / last.R;
        continue;
      }
    }
    out.push_back(c);
  }
  return out;
}

} // namespace

double foster_impedance(const std::vector<FosterCell>& cells, double s) {
  double z = 0;
  for (const FosterCell& c : cells)
    z += c.R / (1 + s * c.R * c.C);
  return z;
}

double cauer_impedance(const std::vector<CauerStage>& stages, double s) {
  double z = 0; // looking into the held far end
  for (auto it = stages.rbegin(); it != stages.rend(); ++it)
    z = 1 / (s * it->C + 1 / (it->R + z));
  return z;
}

double foster_step_response(const std::vector<FosterCell>& cells, double t) {
  double z = 0;
  for (const FosterCell& c : cells)
    z += c.R * -std::expm1(-t / (c.R * c.C));
  return z;
}

std::vector<CauerStage> foster_to_cauer(const std::vector<FosterCell>& input) {
  if (input.empty()) throw FosterError("a Foster network needs at least one cell");
  const std::vector<FosterCell> cells = merged(input);
  const std::size_t n = cells.size();
  // Z(s) = b' (sI + L)^-1 b with L = diag(1/tau_i), b_i = 1/sqrt(C_i); Lanczos from b gives
  // Q' L Q = J (tridiagonal), Q' b = |b| e1, so Z(s) = |b|^2 e1' (sI + J)^-1 e1.
  std::vector<Real> lambda(n), b(n);
  Real norm2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    lambda[i] = 1 / (static_cast<Real>(cells[i].R) * cells[i].C);
    b[i] = 1 / std::sqrt(static_cast<Real>(cells[i].C));
    norm2 += b[i] * b[i];
  }
  std::vector<std::vector<Real>> q;
  std::vector<Real> alpha(n), beta(n, 0);
  std::vector<Real> v(n);
  for (std::size_t i = 0; i < n; ++i)
    v[i] = b[i] / std::sqrt(norm2);
  for (std::size_t k = 0; k < n; ++k) {
    q.push_back(v);
    std::vector<Real> w(n);
    for (std::size_t i = 0; i < n; ++i)
      w[i] = lambda[i] * v[i];
    Real a = 0;
    for (std::size_t i = 0; i < n; ++i)
      a += v[i] * w[i];
    alpha[k] = a;
    // Full reorthogonalisation against every q so far, twice.
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& qj : q) {
        Real d = 0;
        for (std::size_t i = 0; i < n; ++i)
          d += qj[i] * w[i];
        for (std::size_t i = 0; i < n; ++i)
          w[i] -= d * qj[i];
      }
    if (k + 1 == n) break;
    Real nb = 0;
    for (std::size_t i = 0; i < n; ++i)
      nb += w[i] * w[i];
    nb = std::sqrt(nb);
    Real scale = 0;
    for (std::size_t i = 0; i < n; ++i)
      scale = std::max(scale, lambda[i]);
    if (!(nb > 1e-15L * scale))
      throw FosterError("the Foster network's time constants are too close to be told apart");
    beta[k] = nb;
    for (std::size_t i = 0; i < n; ++i)
      v[i] = w[i] / nb;
  }
  // The ladder: C1 = 1/|b|^2; 1/R1 = alpha1 C1; C_{k+1} = 1/(R_k^2 beta_k^2 C_k);
  // 1/R_{k+1} = alpha_{k+1} C_{k+1} - 1/R_k.
  std::vector<CauerStage> out(n);
  Real C = 1 / norm2;
  Real G_prev = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) {
      const Real R_prev = 1 / G_prev;
      C = 1 / (R_prev * R_prev * beta[k - 1] * beta[k - 1] * C);
    }
    const Real G = alpha[k] * C - G_prev;
    if (!(C > 0) || !(G > 0) || !std::isfinite(static_cast<double>(C)) ||
        !std::isfinite(static_cast<double>(G)))
      throw FosterError("the Cauer ladder of this Foster network has a non-positive element "
                        "(time constants too close or too far apart for double precision)");
    out[k] = {static_cast<double>(C), static_cast<double>(1 / G)};
    G_prev = G;
  }
  // Verified, not assumed: the same Z(s) at s = 0 and around every 1/tau.
  std::vector<double> points{0};
  for (const FosterCell& c : cells)
    for (double f : {0.1, 1.0, 10.0})
      points.push_back(f / (c.R * c.C));
  for (double s : points) {
    const double zf = foster_impedance(cells, s);
    const double zc = cauer_impedance(out, s);
    if (!(std::fabs(zc - zf) <= 1e-9 * zf))
      throw FosterError(fmt::format("the Cauer ladder's impedance differs from the Foster "
                                    "network's at s = {:g}/s ({:g} against {:g} K/W)",
                                    s, zc, zf));
  }
  return out;
}

} // namespace thermnet::importer
