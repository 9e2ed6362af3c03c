#include "kernel/core/element.hpp"

namespace thermnet {

void LinearLink::declare(JacobianLayout& layout) {
  aa_ = layout.slot(a_, a_);
  ab_ = layout.slot(a_, b_);
  ba_ = layout.slot(b_, a_);
  bb_ = layout.slot(b_, b_);
}

void LinearLink::stamp(double, const double* T, double* F, double* J) const {
  double q = G_ * (T[a_] - T[b_]);
  F[a_] -= q;
  F[b_] += q;
  if (!J) return;
  J[aa_] -= G_;
  J[ab_] += G_;
  J[ba_] += G_;
  J[bb_] -= G_;
}

} // namespace thermnet
