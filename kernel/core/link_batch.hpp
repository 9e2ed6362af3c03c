#pragma once
/// Constant-conductance links of a network in flat arrays: stamped in one loop without virtual
/// calls or pointer chasing (large networks are mostly such links).

#include "kernel/core/element.hpp"

#include <vector>

namespace thermnet {

/// Linear two-terminal links Q = G (T_a - T_b), stored as structure of arrays.
class LinkBatch {
public:
  /// Appends a link between spec nodes a and b with conductance G (W/K).
  void add(int a, int b, double G);
  /// Number of links.
  std::size_t size() const { return G_.size(); }
  /// Requests the Jacobian slots of every link (as Element::declare).
  void declare(JacobianLayout& layout);
  /// Adds every link's heat flow into F (all nodes, W).
  void stamp_flows(const double* T, double* F) const;
  /// Adds every link's derivatives into J (the slots handed out by declare, W/K).
  void stamp_jacobian(double* J) const;

private:
  struct Ends {
    int a, b;
  };
  std::vector<Ends> ends_;
  std::vector<double> G_;
  std::vector<int> slots_; // aa, ab, ba, bb per link
};

} // namespace thermnet
