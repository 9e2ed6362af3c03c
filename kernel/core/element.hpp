#pragma once
/// The physics interface of element plugins: heat flows stamped into F, derivatives into dF/dT.
///
/// Node indices are those of the NetworkSpec (nodes and boundaries together). T, F and the
/// Jacobian values cover every node: boundary rows and columns map to scratch slots that the
/// kernel discards, so stamping code never branches on whether a terminal is a boundary.

#include "lang/network_spec.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace thermnet {

/// Hands out Jacobian slots for (row, column) node pairs while a network is built.
class JacobianLayout {
public:
  virtual ~JacobianLayout() = default;
  /// The slot of dF_row/dT_col in the Jacobian values array.
  virtual int slot(int row, int col) = 0;
};

/// An element instantiated in a network.
///
/// An element may own internal states (a thermostat's lagged sensor reading): the network
/// integrates them with the temperatures, as unknowns after the nodes' (capacity 1, so their F is
/// their rate of change), and gives them indices after the spec's nodes in the T, F and Jacobian
/// slot arrays its methods receive. They are not temperatures of the network: they carry no heat,
/// are not kept above 0 K and are not written as nodes.
class Element {
public:
  virtual ~Element() = default;
  /// Number of internal states it owns (0 for most elements).
  virtual int state_count() const { return 0; }
  /// Receives the index of its first internal state in the node arrays (called before declare()).
  virtual void assign_states(int /*first*/) {}
  /// Writes its internal states' values at the start into x, from the node temperatures T.
  virtual void initial_states(const double* /*T*/, double* /*x*/) const {}
  /// Name of its internal state k, for messages ("sensor").
  virtual std::string state_name(int /*k*/) const { return "state"; }
  /// Requests the Jacobian entries it stamps (called when the network is built; keep the slots).
  virtual void declare(JacobianLayout& layout) = 0;
  /// Adds heat flows into F (W, into each node) and, unless J is null (only flows wanted),
  /// their derivatives into J (W/K) at time t.
  virtual void stamp(double t, const double* T, double* F, double* J) const = 0;
  /// Appends the times where its inputs jump or bend.
  virtual void breakpoints(std::vector<double>& /*out*/) const {}
  /// Number of event functions it owns (thermostats: 1).
  virtual int event_count() const { return 0; }
  /// Writes its event functions' values into g.
  virtual void events(double /*t*/, const double* /*T*/, double* /*g*/) const {}
  /// Reacts to its event function `which` crossing zero; true if its output changed.
  virtual bool apply_event(int /*which*/, double /*t*/, const double* /*T*/) { return false; }
  /// Sets event state consistent with the temperatures at the start.
  virtual void init_events(double /*t*/, const double* /*T*/) {}
  /// Heat it adds to the network from outside, W (sources), for energy accounting.
  virtual double power_in(double /*t*/, const double* /*T*/) const { return 0.0; }
  /// Heat flowing from its first terminal to its second, W (two-terminal links).
  virtual double flow(double /*t*/, const double* /*T*/) const { return 0.0; }
  /// True when its heat flows (and its states' rates) are affine in the unknowns with a constant
  /// Jacobian: a linear, time-invariant coupling, or a prescribed input that does not depend on
  /// the unknowns (default: false, which is always safe).
  virtual bool affine() const { return false; }
  /// For an affine element: true when its time-varying part is linear between its breakpoints
  /// (a constant, step, pwl or table input, or a sum of constant multiples of them).
  virtual bool piecewise_linear_inputs() const { return true; }
  /// True when its heat flows are affine in the unknowns with a Jacobian constant between its
  /// breakpoints, changing only at them (affine() elements, a link switched by a step schedule).
  virtual bool jacobian_piecewise_constant() const { return affine(); }
  /// What it reads, K, for a sensor (an element whose schema `observes`); nothing otherwise.
  virtual std::optional<double> sensor_reading(const double* /*T*/) const { return std::nullopt; }
  /// Adds into dF how its heat flows change per unit of a parameter at (t, T) when its keys
  /// change at `rates` (d value / d parameter of each key that changes, by name, as signals of the
  /// time; keys not listed stay fixed), for forward sensitivities; false when its kind gives no
  /// such derivative or not for these keys (the kernel then differences the heat flows of the
  /// element built at two values of the parameter).
  virtual bool key_derivative(double /*t*/, const double* /*T*/, const lang::KeySignals& /*rates*/,
                              double* /*dF*/) const {
    return false;
  }
};

/// A two-terminal link with a constant conductance G: Q = G (T_a - T_b).
class LinearLink final : public Element {
public:
  /// A link between nodes a and b.
  LinearLink(int a, int b, double G) : a_(a), b_(b), G_(G) {}
  /// The conductance, W/K.
  double conductance() const { return G_; }
  bool affine() const override { return true; }
  /// First terminal (spec node index).
  int a() const { return a_; }
  /// Second terminal (spec node index).
  int b() const { return b_; }
  void declare(JacobianLayout& layout) override;
  void stamp(double t, const double* T, double* F, double* J) const override;
  double flow(double, const double* T) const override { return G_ * (T[a_] - T[b_]); }

private:
  int a_, b_;
  double G_;
  int aa_ = 0, ab_ = 0, ba_ = 0, bb_ = 0;
};

/// Stamps a two-terminal heat flow Q(Ta, Tb) from a to b with partial derivatives (J may be null).
inline void stamp_link(double* F, double* J, int a, int b, double q, double dq_da, double dq_db,
                       const int slots[4]) {
  F[a] -= q;
  F[b] += q;
  if (!J) return;
  J[slots[0]] -= dq_da;
  J[slots[1]] -= dq_db;
  J[slots[2]] += dq_da;
  J[slots[3]] += dq_db;
}

/// Declares the four slots (aa, ab, ba, bb) of a two-terminal link.
inline void declare_link(JacobianLayout& layout, int a, int b, int slots[4]) {
  slots[0] = layout.slot(a, a);
  slots[1] = layout.slot(a, b);
  slots[2] = layout.slot(b, a);
  slots[3] = layout.slot(b, b);
}

/// A two-terminal element whose heat flow Q(T_a, T_b) from a to b is nonlinear: subclasses give
/// Q and its partial derivatives; declaring, stamping and reporting the flow are done here.
class NonlinearLink : public Element {
public:
  /// A link between nodes a and b.
  NonlinearLink(int a, int b) : a_(a), b_(b) {}
  void declare(JacobianLayout& layout) override { declare_link(layout, a_, b_, slots_); }
  void stamp(double, const double* T, double* F, double* J) const override {
    double dq_da = 0.0, dq_db = 0.0;
    const double q = evaluate(T[a_], T[b_], dq_da, dq_db);
    stamp_link(F, J, a_, b_, q, dq_da, dq_db, slots_);
  }
  double flow(double, const double* T) const override {
    double dq_da = 0.0, dq_db = 0.0;
    return evaluate(T[a_], T[b_], dq_da, dq_db);
  }

protected:
  /// Adds into dF the change of a flow proportional to a strength k whose logarithm changes at
  /// rate d_ln_k (d ln k / d parameter): dQ = Q d_ln_k (for key_derivative()).
  void add_proportional_rate(const double* T, double d_ln_k, double* dF) const {
    double dq_da = 0.0, dq_db = 0.0;
    const double dq = evaluate(T[a_], T[b_], dq_da, dq_db) * d_ln_k;
    dF[a_] -= dq;
    dF[b_] += dq;
  }
  /// Heat flow from a to b in W at temperatures ta, tb (K), with dQ/dTa and dQ/dTb in W/K.
  virtual double evaluate(double ta, double tb, double& dq_da, double& dq_db) const = 0;

private:
  int a_, b_;
  int slots_[4] = {0, 0, 0, 0};
};

} // namespace thermnet
