// integrate_with_energy(): a ThermalSystem around the Network whose extra states (capacity 1) are
// the integrals of every element's terminal heats and of each element's on-time; they do not feed
// back into the temperatures, so the network's own Jacobian serves with a zero diagonal for them.

#include "kernel/core/energy_account.hpp"

namespace thermnet {
namespace {

class EnergyAccountSystem final : public ThermalSystem {
public:
  EnergyAccountSystem(Network& net, EnergyTotals& totals) : net_(net), totals_(totals) {
    n_ = net.size();
    const auto& elements = net.spec().elements;
    for (std::size_t e = 0; e < elements.size(); ++e) {
      offset_.push_back(extra_);
      extra_ += static_cast<int>(elements[e].nodes().size()) + 1; // terminals, then on-time
    }
    totals.switching = net.switching_elements();
    totals.switches.assign(elements.size(), 0);
    capacities_ = net.capacities();
    capacities_.resize(static_cast<std::size_t>(n_ + extra_), 1.0);
    const SparsityPattern& p = net.jacobian_pattern();
    pattern_ = p;
    pattern_.n = n_ + extra_;
    for (int i = 0; i < extra_; ++i) {
      pattern_.col_idx.push_back(n_ + i);
      pattern_.row_ptr.push_back(pattern_.row_ptr.back() + 1);
    }
  }

  int size() const override { return n_ + extra_; }
  int temperature_count() const override { return net_.temperature_count(); }
  const std::vector<double>& capacities() const override { return capacities_; }
  void heat_balance(double t, const double* T, double* F) override {
    net_.heat_balance(t, T, F);
    net_.element_heat(t, T, heat_);
    for (std::size_t e = 0; e < heat_.size(); ++e) {
      double* f = F + n_ + offset_[e];
      double delivered = 0.0;
      for (std::size_t j = 0; j < heat_[e].size(); ++j) {
        f[j] = heat_[e][j];
        delivered += heat_[e][j];
      }
      f[heat_[e].size()] = delivered > 0.0 ? 1.0 : 0.0;
    }
  }
  const SparsityPattern& jacobian_pattern() const override { return pattern_; }
  void jacobian(double t, const double* T, double* values) override {
    net_.jacobian(t, T, values);
    const int nnz = net_.jacobian_pattern().nnz();
    for (int i = 0; i < extra_; ++i)
      values[nnz + i] = 0.0;
  }
  int event_count() const override { return net_.event_count(); }
  void events(double t, const double* T, double* g) override { net_.events(t, T, g); }
  bool apply_events(double t, const double* T, const std::vector<int>& fired) override {
    const std::vector<char> before = on_states(t, T);
    const bool changed = net_.apply_events(t, T, fired);
    const std::vector<char> after = on_states(t, T);
    for (std::size_t e = 0; e < before.size(); ++e)
      if (totals_.switching[e] && before[e] != after[e]) ++totals_.switches[e];
    return changed;
  }
  void init_events(double t, const double* T) override { net_.init_events(t, T); }
  std::vector<double> breakpoints(double t0, double t1) const override {
    return net_.breakpoints(t0, t1);
  }
  std::string unknown_name(int i) const override {
    return i < n_ ? net_.unknown_name(i) : "(energy account)";
  }
  std::string event_name(int k) const override { return net_.event_name(k); }

  /// Copies the accumulated states into the totals.
  void collect(const std::vector<double>& state) {
    for (std::size_t e = 0; e < offset_.size(); ++e) {
      const double* x = state.data() + n_ + offset_[e];
      const std::size_t terminals = net_.spec().elements[e].nodes().size();
      totals_.element_energy.emplace_back(x, x + terminals);
      totals_.on_time.push_back(x[terminals]);
    }
  }

private:
  std::vector<char> on_states(double t, const double* T) {
    net_.element_heat(t, T, heat_);
    std::vector<char> on(heat_.size(), 0);
    for (std::size_t e = 0; e < heat_.size(); ++e) {
      double delivered = 0.0;
      for (double h : heat_[e])
        delivered += h;
      on[e] = delivered > 0.0 ? 1 : 0;
    }
    return on;
  }

  Network& net_;
  EnergyTotals& totals_;
  int n_ = 0;
  int extra_ = 0;
  std::vector<int> offset_;
  std::vector<double> capacities_;
  SparsityPattern pattern_;
  std::vector<std::vector<double>> heat_;
};

} // namespace

SolverStats integrate_with_energy(Network& net, std::vector<double>& T, double t0, double t1,
                                  const std::vector<double>& output_times,
                                  const OutputCallback& out, const SolverOptions& opt,
                                  EnergyTotals& totals) {
  totals = EnergyTotals{};
  totals.t0 = t0;
  totals.t1 = t1;
  const std::size_t nodes = net.spec().nodes.size();
  totals.T_start.resize(nodes);
  net.expand(t0, T.data(), totals.T_start.data());
  EnergyAccountSystem sys(net, totals);
  const auto n = static_cast<std::size_t>(net.size());
  std::vector<double> state = T;
  state.resize(static_cast<std::size_t>(sys.size()), 0.0);
  std::vector<double> temps(n);
  SolverStats stats = integrate(
      sys, state, t0, t1, output_times,
      [&](double t, const std::vector<double>& x) {
        std::copy(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(n), temps.begin());
        out(t, temps);
      },
      opt);
  std::copy(state.begin(), state.begin() + static_cast<std::ptrdiff_t>(n), T.begin());
  totals.T_end.resize(nodes);
  net.expand(t1, T.data(), totals.T_end.data());
  sys.collect(state);
  return stats;
}

} // namespace thermnet
