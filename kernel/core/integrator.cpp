// integrate(): the transient driver over CVODE/IDA steppers — segments between breakpoints,
// events by root-finding, dense output at the requested times, guards against runaway runs.

#include "kernel/core/integrator.hpp"

#include "kernel/core/exact_linear.hpp"

#include "kernel/core/absolute_zero.hpp"
#include "kernel/core/linear_solver_choice.hpp"
#include "kernel/core/system_evaluator.hpp"
#include "kernel/core/transient_stepper.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace thermnet {

namespace {

/// Most events applied without time advancing (beyond the time resolution) before giving up.
constexpr int kMaxEventsAtOneTime = 100;
/// Most consecutive internal steps that do not advance time before giving up.
constexpr int kMaxStalledSteps = 10;
/// Internal steps each restart at an input's corner may take beyond SolverOptions::max_steps
/// (a restart takes two to five on smooth inputs).
constexpr long kStepsPerRestart = 20;

/// Two times closer than this are treated as equal (segments shorter are skipped).
double time_resolution(double a, double b) {
  return 64.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b));
}

/// Consecutive event times closer than this count as "the same time" for the re-firing guard.
double event_resolution(double t) {
  return 1e-12 * std::max(1.0, std::abs(t));
}

/// -1, 0 or +1.
int sign_of(double x) {
  return (x > 0.0) - (x < 0.0);
}

/// The ends of the integration segments: breakpoints strictly inside (t0, t1), then t1.
std::vector<double> segment_ends(const ThermalSystem& sys, double t0, double t1) {
  std::vector<double> stops;
  for (double b : sys.breakpoints(t0, t1))
    if (std::isfinite(b) && b > t0 && b < t1) stops.push_back(b);
  std::sort(stops.begin(), stops.end());
  stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
  stops.push_back(t1);
  return stops;
}

void validate(const ThermalSystem& sys, const std::vector<double>& T, double t0, double t1,
              const std::vector<double>& output_times, const SolverOptions& opt) {
  if (!std::isfinite(t0) || !std::isfinite(t1) || t1 < t0)
    throw std::invalid_argument(fmt::format(
        "integrate: the time span [{}, {}] s is not a finite forward interval", t0, t1));
  if (T.size() != static_cast<std::size_t>(sys.size()))
    throw std::invalid_argument(
        fmt::format("integrate: {} initial temperatures for {} unknowns", T.size(), sys.size()));
  if (!std::is_sorted(output_times.begin(), output_times.end()))
    throw std::invalid_argument("integrate: output times must be sorted");
  if (!(opt.rtol >= 0.0) || !(opt.atol > 0.0) || opt.max_steps <= 0)
    throw std::invalid_argument("integrate: tolerances and max_steps must be positive");
}

/// The first segment that is longer than the time resolution (or the last one).
std::size_t first_segment(const std::vector<double>& stops, double t0) {
  std::size_t seg = 0;
  while (seg + 1 < stops.size() && stops[seg] - t0 <= time_resolution(t0, stops[seg]))
    ++seg;
  return seg;
}

/// The forward sensitivities of a run: the parameters, their values at the start (and at the end
/// afterwards) and the caller's callback.
struct SensitivityRun {
  ParameterDerivatives* derivatives = nullptr;
  std::vector<std::vector<double>>* S = nullptr;
  const SensitivityCallback* out = nullptr;
};

/// Delivers the state (and its sensitivities) at each requested output time, in order, through
/// the caller's callback.
class OutputSchedule {
public:
  /// The times of `times` from t0 on are still to come; states have n unknowns.
  OutputSchedule(const std::vector<double>& times, double t0, int n, const OutputCallback& out,
                 const SensitivityRun* sens = nullptr)
      : times_(times), next_(static_cast<std::size_t>(
                           std::lower_bound(times.begin(), times.end(), t0) - times.begin())),
        buf_(static_cast<std::size_t>(n)), out_(out), sens_(sens) {}

  /// The stepper whose dense output gives the sensitivities (none before it exists).
  void attach(detail::TransientStepper* stepper) { stepper_ = stepper; }

  /// Emits state y, the stepper's current state at time t, for every time up to t still to come.
  void emit_up_to(double t, const double* y) {
    for (; next_ < times_.size() && times_[next_] <= t; ++next_)
      emit_state(times_[next_], y);
  }

  /// Emits every time passed by the step that ended at t in state y: y itself at t, dense output
  /// of the stepper before it.
  void emit_passed(double t, const double* y, detail::TransientStepper& stepper) {
    for (; next_ < times_.size() && times_[next_] <= t; ++next_) {
      const double to = times_[next_];
      if (to == t) {
        emit_state(to, y);
      } else {
        stepper.interpolate(to, buf_.data());
        deliver(to, to);
      }
    }
  }

private:
  /// Emits y at the output time t; the sensitivities are taken at `at` (the state's time).
  void emit_state(double t, const double* y) {
    std::copy(y, y + buf_.size(), buf_.begin());
    deliver(t, stepper_ ? stepper_->current_time() : t);
  }

  void deliver(double t, double at) {
    if (!sens_) {
      if (out_) out_(t, buf_);
      return;
    }
    if (stepper_)
      stepper_->interpolate_sensitivities(at, S_);
    else
      S_ = *sens_->S;
    if (*sens_->out) (*sens_->out)(t, buf_, S_);
  }

  const std::vector<double>& times_;
  std::size_t next_;
  std::vector<double> buf_;
  const OutputCallback& out_;
  const SensitivityRun* sens_;
  detail::TransientStepper* stepper_ = nullptr;
  std::vector<std::vector<double>> S_;
};

/// One transient run over its segments: steps, events and restarts, and the guards against
/// runaway runs (step budget, steps that no longer advance, events that keep firing).
class TransientRun {
public:
  /// A run of `stepper` from t0 through the segments ending at `stops`, starting with `seg`.
  TransientRun(ThermalSystem& sys, detail::SystemEvaluator& ev, detail::TransientStepper& stepper,
               const std::vector<double>& stops, std::size_t seg, double t0,
               const SolverOptions& opt, SolverStats& stats, OutputSchedule& outputs)
      : sys_(sys), ev_(ev), stepper_(stepper), chk_(stepper.checker()),
        step_call_(ev.has_algebraic() ? "IDASolve" : "CVode"), stops_(stops), seg_(seg), opt_(opt),
        stats_(stats), outputs_(outputs), y_(stepper.state()), n_(ev.size()),
        nev_(sys.event_count()), t_(t0), fired_(static_cast<std::size_t>(nev_), 0),
        g0_(static_cast<std::size_t>(nev_)), g1_(static_cast<std::size_t>(nev_)) {}

  /// Switches (thermostats) start from the temperatures they sense, but arithmetic nodes only
  /// have theirs once IDA made the state consistent. Moving the state there from the guess T0 is
  /// a change like any other: an event function that changed sign on the way fires, as it would
  /// in a step.
  /// When no state of the switches is consistent (a thermostat whose reading jumps past its other
  /// threshold at each of its switches), the run fails rather than start from an arbitrary one.
  void settle_initial_events(const std::vector<double>& T0) {
    if (nev_ == 0 || !ev_.has_algebraic()) return;
    std::vector<double> guess(T0.begin(), T0.end());
    for (int pass = 0; jumped_across(guess.data()); ++pass) {
      if (!sys_.apply_events(t_, y_, fired_)) break;
      if (pass == kMaxEventsAtOneTime) fail_event_loop(pass);
      std::copy(y_, y_ + n_, guess.begin());
      stepper_.restart(t_, stops_[seg_]);
    }
  }

  /// Steps to the end of the last segment, emitting the outputs passed on the way.
  void run() {
    for (;;) {
      check_step_budget();
      const double t_before = t_;
      const detail::StepResult r = stepper_.step(stops_[seg_], t_);
      if (r == detail::StepResult::stop_reached) t_ = stops_[seg_];
      // A non-finite heat balance met by a rejected attempt stays on record (for the message)
      // until the integration has passed the time where it occurred.
      if (ev_.nonfinite().seen && t_ > ev_.nonfinite().time) ev_.clear_nonfinite();
      check_progress(r, t_before);
      check_absolute_zero(t_before);
      outputs_.emit_passed(t_, y_, stepper_);
      if (r == detail::StepResult::root_found && !apply_events()) return;
      if (r == detail::StepResult::stop_reached && !next_segment()) return;
    }
  }

private:
  /// Fails once the steps of the whole run reach max_steps.
  /// The restarts at the inputs' corners (a table's rows) are work the run must do: each may take
  /// kStepsPerRestart steps besides max_steps, so that a table of a million rows is integrated.
  void check_step_budget() {
    const long restarts = static_cast<long>(stops_.size()) - 1;
    const long budget = opt_.max_steps + kStepsPerRestart * restarts;
    if (stepper_.steps() >= budget)
      chk_.fail(step_call_, stepper_.too_much_work_flag(),
                stepper_.flag_name(stepper_.too_much_work_flag()),
                restarts == 0
                    ? fmt::format("the maximum of {} internal steps (max_steps) was reached before "
                                  "t = {:.10g} s",
                                  opt_.max_steps, stops_.back())
                    : fmt::format("the maximum of {} internal steps (max_steps {} and {} for each "
                                  "of the {} restarts at the inputs' corners) was reached before "
                                  "t = {:.10g} s",
                                  budget, opt_.max_steps, kStepsPerRestart, restarts,
                                  stops_.back()));
  }

  /// Steps that no longer advance time (typically creeping towards a time where the heat balance
  /// stops being finite) would otherwise run on until max_steps: fails after kMaxStalledSteps.
  void check_progress(detail::StepResult r, double t_before) {
    stalled_steps_ =
        (r == detail::StepResult::advanced && t_ - t_before <= time_resolution(t_, t_before))
            ? stalled_steps_ + 1
            : 0;
    if (stalled_steps_ < kMaxStalledSteps) return;
    if (ev_.nonfinite().seen)
      chk_.fail(step_call_, stepper_.repeated_rhs_flag(),
                stepper_.flag_name(stepper_.repeated_rhs_flag()),
                "the heat balance failed repeatedly (the steps shrank to nothing)");
    chk_.fail(step_call_, 0, "step size underflow",
              "the step size shrank to the round-off of the time (a discontinuity may lack a "
              "breakpoint)");
  }

  /// A temperature below 0 K at the end of the step from t_before fails the run, naming the node
  /// and the time it crossed 0 K (bisected on the step's dense output).
  void check_absolute_zero(double t_before) {
    const int i = detail::coldest_below_absolute_zero(y_, sys_.temperature_count());
    if (i < 0) return;
    const auto iu = static_cast<std::size_t>(i);
    ylook_.resize(static_cast<std::size_t>(n_));
    double lo = t_before, hi = t_;
    for (int k = 0; k < 100 && hi - lo > time_resolution(lo, hi); ++k) {
      const double mid = 0.5 * (lo + hi);
      stepper_.interpolate(mid, ylook_.data());
      (ylook_[iu] < 0.0 ? hi : lo) = mid;
    }
    detail::fail_below_absolute_zero(
        ev_, {.unknown = i, .crossing = hi, .kelvin = y_[i], .reached = t_, .steady = false},
        step_call_);
  }

  /// Restarts at t towards the next segment end far enough away; false when t1 is reached.
  bool restart_at(double t) {
    while (stops_[seg_] - t <= time_resolution(t, stops_[seg_])) {
      if (seg_ + 1 == stops_.size()) return false;
      ++seg_;
    }
    stepper_.restart(t, stops_[seg_]);
    ++stats_.restarts;
    return true;
  }

  /// At the end of a segment: on to the next one; false when it was the last.
  bool next_segment() {
    if (seg_ + 1 == stops_.size()) return false;
    ++seg_;
    return restart_at(t_);
  }

  /// Applies the events of a root, then any immediate re-firings, all at the current time, and
  /// restarts after each; false when that restart reached the end of the run.
  bool apply_events() {
    const int* roots = stepper_.roots();
    std::copy(roots, roots + nev_, fired_.begin());
    while (sys_.apply_events(t_, y_, fired_)) {
      count_events();
      found_.assign(y_, y_ + n_); // the state the switch found
      if (!restart_at(t_)) return false;
      if (!refires(t_) && !jumped_across(found_.data())) break;
    }
    return true;
  }

  /// A restart makes the nodes without heat capacity consistent with the new inputs at once: an
  /// event function that changed sign on that jump (from `before` to the present state) fires, as
  /// it would in a step. Returns whether any did (flagged in `fired_`).
  bool jumped_across(const double* before) {
    if (!ev_.has_algebraic()) return false;
    ev_.events(t_, before, g0_.data());
    ev_.events(t_, y_, g1_.data());
    return events_crossed(g0_, g1_, fired_);
  }

  /// Fails a run whose events keep firing at one time, naming what fired last.
  [[noreturn]] void fail_event_loop(int count) {
    std::vector<std::string> which;
    for (int k = 0; k < nev_; ++k)
      if (fired_[static_cast<std::size_t>(k)] != 0) which.push_back(sys_.event_name(k));
    chk_.fail("apply_events", 0, "event loop",
              fmt::format("events keep firing without time advancing ({} events at this time, the "
                          "last by {}): a switch without hysteresis, or one whose reading jumps "
                          "past its other threshold at its own switch (it senses a node without "
                          "heat capacity that its heat reaches at once); there is no consistent "
                          "state: give that node a capacity, or the thermostat a lag",
                          count, fmt::join(which, ", ")));
  }

  /// Counts the events in `fired_`; fails when events keep firing without time advancing or
  /// their total exceeds max_steps.
  void count_events() {
    stats_.events += std::count_if(fired_.begin(), fired_.end(), [](int f) { return f != 0; });
    events_at_same_time_ =
        std::abs(t_ - last_event_) <= event_resolution(t_) ? events_at_same_time_ + 1 : 1;
    last_event_ = t_;
    if (events_at_same_time_ > kMaxEventsAtOneTime) fail_event_loop(events_at_same_time_ - 1);
    if (stats_.events > opt_.max_steps)
      chk_.fail("apply_events", 0, "event limit",
                fmt::format("more than {} events (max_steps) were applied", opt_.max_steps));
  }

  /// After a restart at an event, an event function that fired may sit exactly on zero (a
  /// switch without hysteresis). CVODE/IDA then ignore its next crossing, so look a little
  /// ahead: if it leaves zero opposite to the way it crossed, it re-fires at once. Returns
  /// whether `fired_` now holds such immediate re-firings.
  bool refires(double t) {
    ev_.events(t, y_, g0_.data());
    bool any_zero = false;
    for (int k = 0; k < nev_; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      any_zero = any_zero || (fired_[ku] != 0 && g0_[ku] == 0.0);
    }
    if (!any_zero) return false;
    ydot_.resize(static_cast<std::size_t>(n_));
    ylook_.resize(static_cast<std::size_t>(n_));
    stepper_.derivative(ydot_.data());
    const double dt =
        std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(t));
    for (std::size_t i = 0; i < ylook_.size(); ++i)
      ylook_[i] = y_[i] + dt * ydot_[i];
    ev_.events(t + dt, ylook_.data(), g1_.data());
    bool any = false;
    for (int k = 0; k < nev_; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      const int s = (fired_[ku] != 0 && g0_[ku] == 0.0) ? sign_of(g1_[ku]) : 0;
      fired_[ku] = (s != 0 && s == -sign_of(fired_[ku])) ? s : 0;
      any = any || fired_[ku] != 0;
    }
    return any;
  }

  ThermalSystem& sys_;
  detail::SystemEvaluator& ev_;
  detail::TransientStepper& stepper_;
  sundials::Checker& chk_;
  const char* step_call_; // the SUNDIALS call named in failures
  const std::vector<double>& stops_;
  std::size_t seg_;
  const SolverOptions& opt_;
  SolverStats& stats_;
  OutputSchedule& outputs_;
  double* y_; // the stepper's state
  int n_;
  int nev_;
  double t_;
  double last_event_ = std::numeric_limits<double>::quiet_NaN();
  int events_at_same_time_ = 0;
  int stalled_steps_ = 0;
  std::vector<int> fired_;
  std::vector<double> g0_, g1_, ydot_, ylook_;
  std::vector<double> found_; // the state an event found, before the restart after it
};

/// With nothing to integrate: an IDA start still makes the arithmetic nodes of T consistent.
void make_consistent(detail::SystemEvaluator& ev, LinearSolverKind kind, const SolverOptions& opt,
                     double t0, std::vector<double>& T, SolverStats& stats) {
  if (ev.size() == 0 || !ev.has_algebraic()) return;
  auto stepper =
      detail::make_ida_stepper(ev, kind, opt, t0, T.data(), t0 + std::max(1.0, std::abs(t0)));
  std::copy(stepper->state(), stepper->state() + ev.size(), T.begin());
  stepper->collect(stats);
}

/// integrate() with or without sensitivities.
SolverStats run_transient(ThermalSystem& sys, std::vector<double>& T, double t0, double t1,
                          const std::vector<double>& output_times, const OutputCallback& out,
                          const SolverOptions& opt, const SensitivityRun* sens) {
  validate(sys, T, t0, t1, output_times, opt);
  detail::SystemEvaluator ev(sys);
  const int n = ev.size();
  if (sens && (sys.event_count() > 0 || ev.has_algebraic()))
    throw std::invalid_argument("integrate: forward sensitivities need a system without events "
                                "and arithmetic nodes");
  const LinearSolverKind kind = detail::resolve_linear_solver(
      opt.linear_solver, n, opt.dense_threshold, opt.krylov_threshold);
  SolverStats stats;
  stats.integrator = ev.has_algebraic() ? "ida" : "cvode-bdf";
  stats.linear_solver = detail::linear_solver_name(kind);
  if (sys.event_count() > 0) sys.init_events(t0, T.data());

  const std::vector<double> stops = segment_ends(sys, t0, t1);
  const std::size_t seg = first_segment(stops, t0);
  OutputSchedule outputs(output_times, t0, n, out, sens);
  // Nothing to integrate: an empty system, or an interval within the time resolution.
  if (n == 0 || stops[seg] - t0 <= time_resolution(t0, stops[seg])) {
    make_consistent(ev, kind, opt, t0, T, stats);
    outputs.emit_up_to(t1, T.data());
    return stats;
  }

  std::unique_ptr<detail::TransientStepper> stepper =
      ev.has_algebraic()
          ? detail::make_ida_stepper(ev, kind, opt, t0, T.data(), stops[seg])
          : detail::make_cvode_stepper(ev, kind, opt, t0, T.data(), stops[seg],
                                       sens ? detail::SensitivityStart{sens->derivatives, sens->S}
                                            : detail::SensitivityStart{});
  outputs.attach(stepper.get());
  const double* y = stepper->state();
  TransientRun run(sys, ev, *stepper, stops, seg, t0, opt, stats, outputs);
  try {
    run.settle_initial_events(T);
    outputs.emit_up_to(t0, y);
    run.run();
    outputs.emit_up_to(t1, y);
  } catch (const SolverError& e) {
    std::copy(y, y + n, T.begin()); // the last state reached
    // An input may explain the failure at its place in the model (a pole, a table's rows).
    sys.explain_failure(e.time, t0, t1, e.flag == stepper->too_much_work_flag());
    throw;
  } catch (...) {
    std::copy(y, y + n, T.begin()); // the last state reached
    throw;
  }
  std::copy(y, y + n, T.begin());
  if (sens) stepper->interpolate_sensitivities(stepper->current_time(), *sens->S);
  stepper->collect(stats);
  return stats;
}

} // namespace

SolverStats integrate(ThermalSystem& sys, std::vector<double>& T, double t0, double t1,
                      const std::vector<double>& output_times, const OutputCallback& out,
                      const SolverOptions& opt) {
  if (opt.exact_linear_max > 0 && sys.size() <= opt.exact_linear_max && sys.piecewise_affine())
    return integrate_exact(sys, T, t0, t1, output_times, out, opt.exact_modes);
  return run_transient(sys, T, t0, t1, output_times, out, opt, nullptr);
}

SolverStats integrate(ThermalSystem& sys, ParameterDerivatives& d, std::vector<double>& T,
                      std::vector<std::vector<double>>& S, double t0, double t1,
                      const std::vector<double>& output_times, const SensitivityCallback& out,
                      const SolverOptions& opt) {
  const auto ns = static_cast<std::size_t>(std::max(0, d.count()));
  if (S.size() != ns)
    throw std::invalid_argument(
        fmt::format("integrate: {} initial sensitivities for {} parameters", S.size(), ns));
  for (const auto& s : S)
    if (s.size() != T.size())
      throw std::invalid_argument("integrate: an initial sensitivity has the wrong size");
  if (ns == 0)
    return integrate(
        sys, T, t0, t1, output_times, [&](double t, const std::vector<double>& x) { out(t, x, S); },
        opt);
  const SensitivityRun sens{&d, &S, &out};
  return run_transient(sys, T, t0, t1, output_times, nullptr, opt, &sens);
}

} // namespace thermnet
