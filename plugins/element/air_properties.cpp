// Dry air properties: quartic interpolation of Incropera Table A.4 (200-400 K).
#include "plugins/element/air_properties.hpp"

#include <algorithm>
#include <array>

namespace thermnet::air {
namespace {

constexpr int n_points = 5;
constexpr std::array<double, n_points> table_T = {200.0, 250.0, 300.0, 350.0, 400.0};
constexpr std::array<double, n_points> table_k = {18.1e-3, 22.3e-3, 26.3e-3, 30.0e-3, 33.8e-3};
constexpr std::array<double, n_points> table_nu = {7.590e-6, 11.44e-6, 15.89e-6, 20.92e-6,
                                                   26.41e-6};
constexpr std::array<double, n_points> table_alpha = {10.3e-6, 15.9e-6, 22.5e-6, 29.9e-6, 38.3e-6};
constexpr std::array<double, n_points> table_Pr = {0.737, 0.720, 0.707, 0.700, 0.690};

/// The barycentric weights 1 / prod_{j != i} (T_i - T_j) of the table points.
constexpr std::array<double, n_points> barycentric_weights() {
  std::array<double, n_points> c{};
  for (int i = 0; i < n_points; ++i) {
    double prod = 1.0;
    for (int j = 0; j < n_points; ++j)
      if (j != i) prod *= table_T[i] - table_T[j];
    c[i] = 1.0 / prod;
  }
  return c;
}
constexpr std::array<double, n_points> weights = barycentric_weights();

/// Lagrange basis values w and derivatives dw of the table points at T.
void lagrange_basis(double T, std::array<double, n_points>& w, std::array<double, n_points>& dw) {
  std::array<double, n_points> d{};
  for (int j = 0; j < n_points; ++j)
    d[j] = T - table_T[j];
  for (int i = 0; i < n_points; ++i) {
    double value = 1.0, slope = 0.0;
    for (int j = 0; j < n_points; ++j) {
      if (j == i) continue;
      // Product rule on the running product: (value * d_j)' = slope * d_j + value.
      slope = slope * d[j] + value;
      value *= d[j];
    }
    w[i] = weights[i] * value;
    dw[i] = weights[i] * slope;
  }
}

/// Dot product of basis weights with a table.
double dot(const std::array<double, n_points>& w, const std::array<double, n_points>& v) {
  double s = 0.0;
  for (int i = 0; i < n_points; ++i)
    s += w[i] * v[i];
  return s;
}

} // namespace

Properties properties(double T) {
  const bool clamped = T < T_min || T > T_max;
  std::array<double, n_points> w{}, dw{};
  lagrange_basis(std::clamp(T, T_min, T_max), w, dw);
  if (clamped) dw.fill(0.0);
  Properties p;
  p.k = dot(w, table_k);
  p.dk = dot(dw, table_k);
  p.nu = dot(w, table_nu);
  p.dnu = dot(dw, table_nu);
  p.alpha = dot(w, table_alpha);
  p.dalpha = dot(dw, table_alpha);
  p.Pr = dot(w, table_Pr);
  p.dPr = dot(dw, table_Pr);
  return p;
}

} // namespace thermnet::air
