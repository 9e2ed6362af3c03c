#include "kernel/core/requirement_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermnet {

using lang::RequirementKind;

namespace {
constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double time_eps = 1e-9;

std::size_t at(int i) {
  return static_cast<std::size_t>(i);
}
} // namespace

RequirementCheck::RequirementCheck(const lang::NetworkSpec& spec) : spec_(spec) {
  states_.resize(spec.requirements.size());
  for (std::size_t k = 0; k < spec.requirements.size(); ++k) {
    const auto& r = spec.requirements[k];
    states_[k].slack = inf;
    states_[k].member_energy.assign(r.members.size(), 0.0);
    states_[k].member_last.assign(r.members.size(), 0.0);
    needs_heat_ = needs_heat_ || r.kind == RequirementKind::power ||
                  r.kind == RequirementKind::energy || r.kind == RequirementKind::margin;
  }
}

void RequirementCheck::update(State& s, double slack, double worst, double t,
                              const std::string& where) const {
  if (slack < s.slack) {
    s.slack = slack;
    s.worst = worst;
    s.time = t;
    s.where = where;
  }
}

void RequirementCheck::add(double t, const std::vector<double>& temps,
                           const std::vector<std::vector<double>>& heat) {
  for (std::size_t k = 0; k < states_.size(); ++k) {
    const auto& r = spec_.requirements[k];
    State& s = states_[k];
    if (t < r.from - time_eps) continue;
    const auto power_of = [&](int e) { return heat[at(e)][0]; };
    switch (r.kind) {
    case RequirementKind::band:
      for (int i : r.members) {
        const double T = temps[at(i)];
        const double slack = std::min(T - r.lo, r.hi - T);
        if (slack < s.slack) update(s, slack, T, t, spec_.nodes[at(i)].name);
      }
      break;
    case RequirementKind::gradient: {
      // One group: its spread; two groups: the largest difference between a member of each.
      const auto extreme = [&](const std::vector<int>& g, bool high) {
        int best = g.front();
        for (int i : g)
          if (high ? temps[at(i)] > temps[at(best)] : temps[at(i)] < temps[at(best)]) best = i;
        return best;
      };
      const std::vector<int>& a = r.members;
      const std::vector<int>& b = r.others.empty() ? r.members : r.others;
      int hi = extreme(a, true), lo = extreme(b, false);
      const int hi2 = extreme(b, true), lo2 = extreme(a, false);
      if (temps[at(hi2)] - temps[at(lo2)] > temps[at(hi)] - temps[at(lo)]) {
        hi = hi2;
        lo = lo2;
      }
      const double spread = temps[at(hi)] - temps[at(lo)];
      if (r.hi - spread < s.slack)
        update(s, r.hi - spread, spread, t,
               fmt::format("{} - {}", spec_.nodes[at(hi)].name, spec_.nodes[at(lo)].name));
      break;
    }
    case RequirementKind::power:
    case RequirementKind::energy:
    case RequirementKind::margin: {
      double total = 0.0;
      for (std::size_t m = 0; m < r.members.size(); ++m) {
        const double p = power_of(r.members[m]);
        total += p;
        if (s.seen) s.member_energy[m] += 0.5 * (p + s.member_last[m]) * (t - s.last_t);
        s.member_last[m] = p;
      }
      if (s.seen)
        s.energy += 0.5 * (total + s.last_power) * (t - s.last_t);
      else
        s.first_t = t;
      if (r.kind == RequirementKind::power && r.hi - total < s.slack)
        update(s, r.hi - total, total, t, "");
      s.last_power = total;
      break;
    }
    }
    s.last_t = t;
    s.seen = true;
  }
}

std::vector<RequirementOutcome> RequirementCheck::outcomes() const {
  std::vector<RequirementOutcome> out;
  for (std::size_t k = 0; k < states_.size(); ++k) {
    const auto& r = spec_.requirements[k];
    const State& s = states_[k];
    RequirementOutcome o;
    o.req = &r;
    o.case_name = spec_.settings.name;
    o.slack = s.slack;
    o.worst = s.worst;
    o.time = s.time;
    o.where = s.where;
    if (r.kind == RequirementKind::energy) {
      o.worst = s.energy;
      o.slack = r.hi - s.energy;
      o.time = s.last_t;
    } else if (r.kind == RequirementKind::margin) {
      // The members together: their installed P over the mean power they deliver, minus 1.
      const double span = s.last_t - s.first_t;
      double installed = 0.0, energy = 0.0;
      for (std::size_t m = 0; m < r.members.size(); ++m) {
        installed += spec_.elements[at(r.members[m])].number("P");
        energy += s.member_energy[m];
      }
      const double mean = span > 0 ? energy / span : 0.0;
      o.worst = mean > 0 && installed > 0 ? installed / mean - 1.0 : inf;
      o.slack = o.worst - r.lo;
      o.duty = installed > 0 ? mean / installed : 0.0;
      o.where = "";
      o.time = s.last_t;
    }
    if (!s.seen) { // nothing after `from`: the run is shorter than the requirement's start
      o.slack = -inf;
      o.where = "(no output at or after the requirement's 'from' time)";
    }
    o.met = o.slack >= 0;
    out.push_back(std::move(o));
  }
  return out;
}

OutcomeFields outcome_fields(const RequirementOutcome& o, const lang::SourceManager& sources) {
  const auto& r = *o.req;
  OutcomeFields f;
  f.file = sources.path(r.where.file);
  const auto lc = sources.line_col(r.where.file, r.where.begin);
  f.line = lc.line;
  f.column = lc.column;
  f.kind = lang::requirement_keyword(r.kind);
  f.text = r.text;
  f.unit = r.unit.text;
  const bool absolute = r.kind == RequirementKind::band;
  f.worst = absolute || r.kind == RequirementKind::margin || r.kind == RequirementKind::power ||
                    r.kind == RequirementKind::energy
                ? r.unit.shown(o.worst)
                : r.unit.shown_difference(o.worst);
  f.slack = r.unit.shown_difference(o.slack);
  return f;
}

std::string format_outcome(const RequirementOutcome& o, const lang::SourceManager& sources) {
  const OutcomeFields f = outcome_fields(o, sources);
  const auto& r = *o.req;
  const std::string head = fmt::format("{}:{}:{}: requirement {}: {} (case {})", f.file, f.line,
                                       f.column, o.met ? "met" : "VIOLATED", f.text, o.case_name);
  if (!std::isfinite(o.slack)) {
    if (o.slack > 0) return head + ": no power delivered (margin unbounded)";
    return head + ": " + o.where;
  }
  std::string what;
  switch (r.kind) {
  case RequirementKind::band:
    what = fmt::format("worst {} = {:.2f} {} at t = {:g} s", o.where, f.worst, f.unit, o.time);
    break;
  case RequirementKind::gradient:
    what = fmt::format("largest difference {} = {:.2f} {} at t = {:g} s", o.where, f.worst, f.unit,
                       o.time);
    break;
  case RequirementKind::power:
    what = fmt::format("peak power {:.4g} {} at t = {:g} s", f.worst, f.unit, o.time);
    break;
  case RequirementKind::energy:
    what = fmt::format("energy {:.4g} {}", f.worst, f.unit);
    break;
  case RequirementKind::margin:
    what = fmt::format("installed power {:.1f} {} above the mean delivered (duty {:.1f} %)",
                       f.worst, f.unit, 100 * o.duty);
    break;
  }
  return fmt::format("{}: {}; {} {:.3g} {}", head, what, o.met ? "margin" : "violated by",
                     std::abs(f.slack), f.unit);
}

} // namespace thermnet
