#pragma once
/// A network's parameter derivatives, known from its elaborations at moved parameter values (no
/// simulation): the capacities, initial temperatures, boundary temperatures and element keys a
/// parameter moves, differentiated piece by piece.

#include "kernel/core/network.hpp"
#include "kernel/core/parameter_derivatives.hpp"

#include <memory>
#include <string>
#include <vector>

namespace thermnet {

/// The network elaborated with one parameter moved.
struct MovedSpec {
  lang::NetworkSpec spec; ///< the network at p + step e_j
  double step = 0.0;      ///< how far p_j moved (non-zero; negative at an upper bound)
  double scale = 1.0;     ///< a typical size of p_j
};

/// dF/dp, dC/dp and dT(0)/dp of a network along each moved spec. A piece (a link or element) whose
/// keys or terminal boundaries moved is differentiated: a linear link through its conductance, an
/// element by its kind's key derivative (Element::key_derivative) or, when the kind gives none or
/// a boundary it touches moved, by the difference of its heat flows between its two builds.
class NetworkDerivatives final : public ParameterDerivatives {
public:
  /// The derivatives of `net` (kept by reference) along the moved specs, built with `registry`.
  NetworkDerivatives(Network& net, std::vector<MovedSpec> moved,
                     const ElementRegistry& registry = ElementRegistry::global());
  ~NetworkDerivatives() override;
  NetworkDerivatives(const NetworkDerivatives&) = delete;            ///< not copyable
  NetworkDerivatives& operator=(const NetworkDerivatives&) = delete; ///< not copyable

  /// True when forward sensitivities can be integrated (see why_not()).
  bool supported() const { return why_not_.empty(); }
  /// Why they cannot (events, arithmetic nodes, internal states, a steady start, a parameter that
  /// changes the structure); empty when supported.
  const std::string& why_not() const { return why_not_; }
  /// True when parameter j moves nothing of the network (its sensitivities stay zero).
  bool inert(int j) const;
  /// Pieces parameter j moves.
  std::size_t moved_pieces(int j) const;
  /// Of those, the pieces differentiated by the difference of their two builds (a kind that
  /// refuses its key derivative is known once heat_balance() asked it).
  std::size_t differenced_pieces(int j) const;
  /// Writes d(temperature)/dp_j at t of every spec node that is a boundary into `all` (one entry
  /// per spec node; the others are left as they are).
  void boundary_derivative(int j, double t, double* all) const;

  int count() const override { return static_cast<int>(dirs_.size()); }
  double scale(int j) const override;
  void heat_balance(int j, double t, const double* T, double* dF) override;
  const std::vector<double>& capacities(int j) const override;
  const std::vector<double>& initial_state(int j) const override;

private:
  struct Direction;
  void check_network();
  void prepare(Direction& d);

  Network& net_;
  std::vector<std::unique_ptr<Direction>> dirs_;
  std::vector<const lang::ElementSpec*> piece_specs_; // the spec element (or part) of each piece
  std::vector<double> F_, A_, B_;                     // scratch over the node arrays
  std::string why_not_;
};

} // namespace thermnet
