#pragma once
/// The equations the integrators solve: C_i dT_i/dt = F_i(t, T), with events and breakpoints.

#include <string>
#include <vector>

namespace thermnet {

/// A sparsity pattern in compressed sparse row form over the unknowns (diagonal always present).
struct SparsityPattern {
  int n = 0;                ///< number of rows and columns
  std::vector<int> row_ptr; ///< row starts, size n + 1
  std::vector<int> col_idx; ///< column of each stored entry, sorted within a row
  /// Number of stored entries.
  int nnz() const { return row_ptr.empty() ? 0 : row_ptr.back(); }
};

/// A lumped thermal system C_i dT_i/dt = F_i(t, T) in kelvin; C_i = 0 marks an algebraic
/// (arithmetic) node.
///
/// Implementations (the kernel's Network) stamp element heat flows into F and their derivatives
/// into dF/dT at entries of a pattern fixed when the system is built. Inputs may switch at
/// breakpoints (step/pwl corners) and at events (thermostat thresholds, found by root-finding).
class ThermalSystem {
public:
  virtual ~ThermalSystem() = default;
  /// Number of unknowns.
  virtual int size() const = 0;
  /// Number of leading unknowns that are temperatures (the rest, if any, are accounts such as
  /// energies, which may be negative).
  virtual int temperature_count() const { return size(); }
  /// Heat capacity of each unknown in J/K (0 for an algebraic node).
  virtual const std::vector<double>& capacities() const = 0;
  /// Net heat flow into each unknown, F(t, T), in W.
  virtual void heat_balance(double t, const double* T, double* F) = 0;
  /// The fixed pattern of dF/dT.
  virtual const SparsityPattern& jacobian_pattern() const = 0;
  /// Values of dF/dT at (t, T), in the order of jacobian_pattern() entries, in W/K.
  virtual void jacobian(double t, const double* T, double* values) = 0;

  /// Number of event functions (e.g. one per thermostat).
  virtual int event_count() const { return 0; }
  /// Event functions g(t, T); an event fires where one crosses zero.
  virtual void events(double /*t*/, const double* /*T*/, double* /*g*/) {}
  /// Applies the events flagged in `fired` (one flag per event function); true if any input
  /// changed.
  virtual bool apply_events(double /*t*/, const double* /*T*/, const std::vector<int>& /*fired*/) {
    return false;
  }
  /// Sets event-driven state (thermostats on/off) consistent with T at the start time.
  virtual void init_events(double /*t*/, const double* /*T*/) {}

  /// Times strictly inside (t0, t1] where inputs are discontinuous; the integrator restarts there.
  virtual std::vector<double> breakpoints(double /*t0*/, double /*t1*/) const { return {}; }
  /// True when F(t, T) = J T + f(t) with J constant, f linear between breakpoints and no events
  /// (integrate() may then solve it exactly: exact_linear.hpp). Default: false.
  virtual bool piecewise_linear() const { return false; }
  /// piecewise_linear(), or the same with J constant only between breakpoints (a link switched by
  /// a step schedule): integrate() may still solve it exactly, one J per piece. Default: as
  /// piecewise_linear().
  virtual bool piecewise_affine() const { return piecewise_linear(); }

  /// After the integrators failed at time t of a run over [t0, t1] (out of steps when
  /// `out_of_steps`): throws a located error when an input explains it (an expression with a pole
  /// near t, an input whose corners took the steps); returns otherwise.
  virtual void explain_failure(double /*t*/, double /*t0*/, double /*t1*/,
                               bool /*out_of_steps*/) const {}

  /// Name of an unknown for messages (the node name).
  virtual std::string unknown_name(int i) const { return "#" + std::to_string(i); }
  /// What owns event function k, for messages ("thermostat 'th'").
  virtual std::string event_name(int k) const { return "event function #" + std::to_string(k); }
};

/// A ThermalSystem that hands every call to another one; subclasses override what they change
/// (an extra heat input, a record of the events applied).
class ForwardingSystem : public ThermalSystem {
public:
  /// Forwards to `inner` (which must outlive it).
  explicit ForwardingSystem(ThermalSystem& inner) : inner_(inner) {}
  int size() const override { return inner_.size(); }
  int temperature_count() const override { return inner_.temperature_count(); }
  const std::vector<double>& capacities() const override { return inner_.capacities(); }
  void heat_balance(double t, const double* T, double* F) override { inner_.heat_balance(t, T, F); }
  const SparsityPattern& jacobian_pattern() const override { return inner_.jacobian_pattern(); }
  void jacobian(double t, const double* T, double* values) override {
    inner_.jacobian(t, T, values);
  }
  int event_count() const override { return inner_.event_count(); }
  void events(double t, const double* T, double* g) override { inner_.events(t, T, g); }
  bool apply_events(double t, const double* T, const std::vector<int>& fired) override {
    return inner_.apply_events(t, T, fired);
  }
  void init_events(double t, const double* T) override { inner_.init_events(t, T); }
  std::vector<double> breakpoints(double t0, double t1) const override {
    return inner_.breakpoints(t0, t1);
  }
  void explain_failure(double t, double t0, double t1, bool out_of_steps) const override {
    inner_.explain_failure(t, t0, t1, out_of_steps);
  }
  std::string unknown_name(int i) const override { return inner_.unknown_name(i); }
  std::string event_name(int k) const override { return inner_.event_name(k); }

private:
  ThermalSystem& inner_;
};

/// Flags in `crossed` the event functions whose sign changed from `before` to `after` (+1 rising,
/// -1 falling, 0 not), as a step between the two states would fire them; true when any did.
inline bool events_crossed(const std::vector<double>& before, const std::vector<double>& after,
                           std::vector<int>& crossed) {
  const auto sign = [](double x) { return (x > 0.0) - (x < 0.0); };
  bool any = false;
  for (std::size_t k = 0; k < crossed.size(); ++k) {
    const int s = sign(after[k]);
    crossed[k] = (s != 0 && s != sign(before[k])) ? s : 0;
    any = any || crossed[k] != 0;
  }
  return any;
}

} // namespace thermnet
