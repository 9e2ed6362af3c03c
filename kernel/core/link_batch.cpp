#include "kernel/core/link_batch.hpp"

namespace thermnet {

void LinkBatch::add(int a, int b, double G) {
  ends_.push_back({a, b});
  G_.push_back(G);
}

void LinkBatch::declare(JacobianLayout& layout) {
  slots_.resize(4 * ends_.size());
  for (std::size_t k = 0; k < ends_.size(); ++k)
    declare_link(layout, ends_[k].a, ends_[k].b, &slots_[4 * k]);
}

void LinkBatch::stamp_flows(const double* T, double* F) const {
  const std::size_t n = G_.size();
  const Ends* ends = ends_.data();
  const double* G = G_.data();
  for (std::size_t k = 0; k < n; ++k) {
    const int a = ends[k].a, b = ends[k].b;
    const double q = G[k] * (T[a] - T[b]);
    F[a] -= q;
    F[b] += q;
  }
}

void LinkBatch::stamp_jacobian(double* J) const {
  const std::size_t n = G_.size();
  const int* s = slots_.data();
  for (std::size_t k = 0; k < n; ++k, s += 4) {
    const double g = G_[k];
    J[s[0]] -= g;
    J[s[1]] += g;
    J[s[2]] += g;
    J[s[3]] -= g;
  }
}

} // namespace thermnet
