// integrate(): the transient driver over CVODE/IDA steppers — segments between breakpoints,
// events by root-finding, dense output at the requested times, guards against runaway runs.

#include "kernel/core/integrator.hpp"

#include "kernel/core/linear_solver_choice.hpp"
#include "kernel/core/system_evaluator.hpp"
#include "kernel/core/transient_stepper.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace thermnet {

namespace {

/// Most events applied without time advancing (beyond the time resolution) before giving up.
constexpr int kMaxEventsAtOneTime = 100;
/// Most consecutive internal steps that do not advance time before giving up.
constexpr int kMaxStalledSteps = 10;

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

} // namespace

SolverStats integrate(ThermalSystem& sys, std::vector<double>& T, double t0, double t1,
                      const std::vector<double>& output_times, const OutputCallback& out,
                      const SolverOptions& opt) {
  validate(sys, T, t0, t1, output_times, opt);
  detail::SystemEvaluator ev(sys);
  const int n = ev.size();
  const LinearSolverKind kind = detail::resolve_linear_solver(
      opt.linear_solver, n, opt.dense_threshold, opt.krylov_threshold);

  SolverStats stats;
  stats.integrator = ev.has_algebraic() ? "ida" : "cvode-bdf";
  stats.linear_solver = detail::linear_solver_name(kind);

  const int nev = sys.event_count();
  if (nev > 0) sys.init_events(t0, T.data());

  const std::vector<double> stops = segment_ends(sys, t0, t1);
  std::size_t seg = 0;
  while (seg + 1 < stops.size() && stops[seg] - t0 <= time_resolution(t0, stops[seg]))
    ++seg;

  auto next_out = static_cast<std::size_t>(
      std::lower_bound(output_times.begin(), output_times.end(), t0) - output_times.begin());
  std::vector<double> buf(static_cast<std::size_t>(n));
  const auto emit_state = [&](double t, const double* y) {
    std::copy(y, y + n, buf.begin());
    if (out) out(t, buf);
  };
  const auto emit_remaining = [&](const double* y) {
    for (; next_out < output_times.size() && output_times[next_out] <= t1; ++next_out)
      emit_state(output_times[next_out], y);
  };

  // Nothing to integrate: an empty system, or an interval within the time resolution.
  if (n == 0 || stops[seg] - t0 <= time_resolution(t0, stops[seg])) {
    if (n > 0 && ev.has_algebraic()) { // still make the arithmetic nodes consistent
      auto stepper =
          detail::make_ida_stepper(ev, kind, opt, t0, T.data(), t0 + std::max(1.0, std::abs(t0)));
      std::copy(stepper->state(), stepper->state() + n, T.begin());
      stepper->collect(stats);
    }
    emit_remaining(T.data());
    return stats;
  }

  std::unique_ptr<detail::TransientStepper> stepper =
      ev.has_algebraic() ? detail::make_ida_stepper(ev, kind, opt, t0, T.data(), stops[seg])
                         : detail::make_cvode_stepper(ev, kind, opt, t0, T.data(), stops[seg]);
  double* y = stepper->state();
  sundials::Checker& chk = stepper->checker();
  const char* step_call = ev.has_algebraic() ? "IDASolve" : "CVode";

  try {
    // Switches (thermostats) start from the temperatures they sense, but arithmetic nodes only
    // have theirs once IDA made the state consistent. Moving the state there is a change like
    // any other: an event function that changed sign on the way fires, as it would in a step.
    if (nev > 0 && ev.has_algebraic()) {
      std::vector<double> g_guess(static_cast<std::size_t>(nev)), g_ic(g_guess.size());
      std::vector<int> crossed(g_guess.size());
      std::vector<double> guess(T.begin(), T.end());
      for (int pass = 0; pass < 4; ++pass) {
        ev.events(t0, guess.data(), g_guess.data());
        ev.events(t0, y, g_ic.data());
        if (!events_crossed(g_guess, g_ic, crossed) || !sys.apply_events(t0, y, crossed)) break;
        std::copy(y, y + n, guess.begin());
        stepper->restart(t0, stops[seg]);
      }
    }
    for (; next_out < output_times.size() && output_times[next_out] <= t0; ++next_out)
      emit_state(output_times[next_out], y);

    // Restarts at t towards the next segment end far enough away; false when t1 is reached.
    const auto restart_at = [&](double t) {
      while (stops[seg] - t <= time_resolution(t, stops[seg])) {
        if (seg + 1 == stops.size()) return false;
        ++seg;
      }
      stepper->restart(t, stops[seg]);
      ++stats.restarts;
      return true;
    };

    std::vector<int> fired(static_cast<std::size_t>(nev), 0);
    std::vector<double> g0(static_cast<std::size_t>(nev)), g1(static_cast<std::size_t>(nev));
    std::vector<double> ydot, ylook;

    // After a restart at an event, an event function that fired may sit exactly on zero (a
    // switch without hysteresis). CVODE/IDA then ignore its next crossing, so look a little
    // ahead: if it leaves zero opposite to the way it crossed, it re-fires at once. Returns
    // whether `fired` now holds such immediate re-firings.
    const auto refires = [&](double t) {
      ev.events(t, y, g0.data());
      bool any_zero = false;
      for (int k = 0; k < nev; ++k) {
        const auto ku = static_cast<std::size_t>(k);
        any_zero = any_zero || (fired[ku] != 0 && g0[ku] == 0.0);
      }
      if (!any_zero) return false;
      ydot.resize(static_cast<std::size_t>(n));
      ylook.resize(static_cast<std::size_t>(n));
      stepper->derivative(ydot.data());
      const double dt =
          std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(t));
      for (std::size_t i = 0; i < ylook.size(); ++i)
        ylook[i] = y[i] + dt * ydot[i];
      ev.events(t + dt, ylook.data(), g1.data());
      bool any = false;
      for (int k = 0; k < nev; ++k) {
        const auto ku = static_cast<std::size_t>(k);
        const int s = (fired[ku] != 0 && g0[ku] == 0.0) ? sign_of(g1[ku]) : 0;
        fired[ku] = (s != 0 && s == -sign_of(fired[ku])) ? s : 0;
        any = any || fired[ku] != 0;
      }
      return any;
    };

    double t = t0;
    double last_event = std::numeric_limits<double>::quiet_NaN();
    int events_at_same_time = 0;
    int stalled_steps = 0;
    bool finished = false;
    while (!finished) {
      if (stepper->steps() >= opt.max_steps)
        chk.fail(step_call, stepper->too_much_work_flag(),
                 stepper->flag_name(stepper->too_much_work_flag()),
                 fmt::format("the maximum of {} internal steps (max_steps) was reached before "
                             "t = {:.10g} s",
                             opt.max_steps, t1));
      const double end = stops[seg];
      const double t_before = t;
      const detail::StepResult r = stepper->step(end, t);
      if (r == detail::StepResult::stop_reached) t = end;

      // A non-finite heat balance met by a rejected attempt stays on record (for the message)
      // until the integration has passed the time where it occurred.
      if (ev.nonfinite().seen && t > ev.nonfinite().time) ev.clear_nonfinite();
      // Steps that no longer advance time (typically creeping towards a time where the heat
      // balance stops being finite) would otherwise run on until max_steps.
      stalled_steps =
          (r == detail::StepResult::advanced && t - t_before <= time_resolution(t, t_before))
              ? stalled_steps + 1
              : 0;
      if (stalled_steps >= kMaxStalledSteps) {
        if (ev.nonfinite().seen)
          chk.fail(step_call, stepper->repeated_rhs_flag(),
                   stepper->flag_name(stepper->repeated_rhs_flag()),
                   "the heat balance failed repeatedly (the steps shrank to nothing)");
        chk.fail(step_call, 0, "step size underflow",
                 "the step size shrank to the round-off of the time (a discontinuity may lack a "
                 "breakpoint)");
      }

      // Dense output for every requested time passed by this step.
      for (; next_out < output_times.size() && output_times[next_out] <= t; ++next_out) {
        const double to = output_times[next_out];
        if (to == t) {
          emit_state(to, y);
        } else {
          stepper->interpolate(to, buf.data());
          if (out) out(to, buf);
        }
      }

      if (r == detail::StepResult::root_found) {
        const int* roots = stepper->roots();
        std::copy(roots, roots + nev, fired.begin());
        // Apply the events, then any immediate re-firings, all at time t.
        while (sys.apply_events(t, y, fired)) {
          stats.events += std::count_if(fired.begin(), fired.end(), [](int f) { return f != 0; });
          events_at_same_time =
              std::abs(t - last_event) <= event_resolution(t) ? events_at_same_time + 1 : 1;
          last_event = t;
          if (events_at_same_time > kMaxEventsAtOneTime) {
            std::vector<std::string> which;
            for (int k = 0; k < nev; ++k)
              if (fired[static_cast<std::size_t>(k)] != 0) which.push_back(fmt::format("#{}", k));
            chk.fail("apply_events", 0, "event loop",
                     fmt::format("events keep firing without time advancing ({} events at this "
                                 "time, the last by event function {}); a thermostat or switch "
                                 "probably has no hysteresis",
                                 events_at_same_time - 1, fmt::join(which, ", ")));
          }
          if (stats.events > opt.max_steps)
            chk.fail("apply_events", 0, "event limit",
                     fmt::format("more than {} events (max_steps) were applied", opt.max_steps));
          if (!restart_at(t)) {
            finished = true;
            break;
          }
          if (!refires(t)) break;
        }
        continue;
      }
      if (r == detail::StepResult::stop_reached) {
        if (seg + 1 == stops.size()) break;
        ++seg;
        if (!restart_at(t)) break;
      }
    }
    emit_remaining(y);
  } catch (...) {
    std::copy(y, y + n, T.begin()); // the last state reached
    throw;
  }
  std::copy(y, y + n, T.begin());
  stepper->collect(stats);
  return stats;
}

} // namespace thermnet
