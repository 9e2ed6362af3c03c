// The hypotheses the engine composes from the plugins' ones: applied findings with a free candidate
// on top (Stack), a candidate refitted with the ranged params (Joint), several candidates refitted
// together (Compose).

#include "kernel/diagnosis/composites.hpp"

#include <algorithm>

namespace thermnet::detail {

lang::ParamValues Stack::overrides(const Candidate&, const std::vector<double>& p) const {
  lang::ParamValues v;
  for (const auto& a : *applied_)
    for (auto& [k, x] : a.h->overrides(a.c, a.p))
      v.insert_or_assign(k, x);
  if (free_)
    for (auto& [k, x] : free_->overrides(*fc_, p))
      v.insert_or_assign(k, x);
  return v;
}

void Stack::extend(const Candidate&, const std::vector<double>& p, lang::NetworkSpec& spec) const {
  for (const auto& a : *applied_)
    a.h->extend(a.c, a.p, spec);
  if (free_) free_->extend(*fc_, p, spec);
}

bool Stack::corrects(const Candidate&) const {
  return std::any_of(applied_->begin(), applied_->end(),
                     [](const Applied& a) { return a.h->corrects(a.c); }) ||
         (free_ && free_->corrects(*fc_));
}

void Stack::correct(const Candidate&, const std::vector<double>& p, int node,
                    const std::vector<double>& times, std::vector<double>& sim) const {
  for (const auto& a : *applied_)
    a.h->correct(a.c, a.p, node, times, sim);
  if (free_) free_->correct(*fc_, p, node, times, sim);
}

std::string Stack::statement(const Candidate&, const std::vector<double>& p,
                             const Evidence& ev) const {
  return free_ ? free_->statement(*fc_, p, ev) : std::string();
}

CaseLines Stack::case_statements(const Candidate&, const std::vector<double>& p,
                                 const Evidence& ev) const {
  return free_ ? free_->case_statements(*fc_, p, ev) : CaseLines();
}

lang::ParamValues Stack::rewrites(const Candidate&, const std::vector<double>& p) const {
  return free_ ? free_->rewrites(*fc_, p) : lang::ParamValues();
}

std::vector<std::string> Stack::retires(const Candidate&, const Evidence& ev) const {
  return free_ ? free_->retires(*fc_, ev) : std::vector<std::string>();
}

Candidate Compose::candidate() const {
  Candidate c;
  c.measurement_side = true;
  for (const auto& a : parts_) {
    c.kind += (c.kind.empty() ? "" : "+") + a.c.kind;
    c.names.insert(c.names.end(), a.c.names.begin(), a.c.names.end());
    c.start.insert(c.start.end(), a.p.begin(), a.p.end());
    c.lo.insert(c.lo.end(), a.c.lo.begin(), a.c.lo.end());
    c.hi.insert(c.hi.end(), a.c.hi.begin(), a.c.hi.end());
    // (a part refitted with the ranged params changes the model: it is simulated)
    c.measurement_side = c.measurement_side && a.c.measurement_side && !a.h->recalibrates();
  }
  return c;
}

std::vector<double> Compose::slice(const std::vector<double>& p, std::size_t i) const {
  std::size_t from = 0;
  for (std::size_t j = 0; j < i; ++j)
    from += parts_[j].c.start.size();
  const auto b = p.begin() + static_cast<long>(from);
  return {b, b + static_cast<long>(parts_[i].c.start.size())};
}

lang::ParamValues Compose::overrides(const Candidate&, const std::vector<double>& p) const {
  lang::ParamValues v;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    for (auto& [k, x] : parts_[i].h->overrides(parts_[i].c, slice(p, i)))
      v.insert_or_assign(k, x);
  return v;
}

void Compose::extend(const Candidate&, const std::vector<double>& p,
                     lang::NetworkSpec& spec) const {
  for (std::size_t i = 0; i < parts_.size(); ++i)
    parts_[i].h->extend(parts_[i].c, slice(p, i), spec);
}

bool Compose::corrects(const Candidate&) const {
  return std::any_of(parts_.begin(), parts_.end(),
                     [](const Applied& a) { return a.h->corrects(a.c); });
}

void Compose::correct(const Candidate&, const std::vector<double>& p, int node,
                      const std::vector<double>& times, std::vector<double>& sim) const {
  for (std::size_t i = 0; i < parts_.size(); ++i)
    parts_[i].h->correct(parts_[i].c, slice(p, i), node, times, sim);
}

std::string Compose::statement(const Candidate&, const std::vector<double>& p,
                               const Evidence& ev) const {
  std::string s;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    s.append(i ? "\n" : "").append(parts_[i].h->statement(parts_[i].c, slice(p, i), ev));
  return s;
}

CaseLines Compose::case_statements(const Candidate&, const std::vector<double>& p,
                                   const Evidence& ev) const {
  CaseLines lines;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    merge_case_lines(lines, parts_[i].h->case_statements(parts_[i].c, slice(p, i), ev));
  return lines;
}

lang::ParamValues Compose::rewrites(const Candidate&, const std::vector<double>& p) const {
  lang::ParamValues v;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    for (auto& [k, x] : parts_[i].h->rewrites(parts_[i].c, slice(p, i)))
      v.insert_or_assign(k, x);
  return v;
}

std::vector<std::string> Compose::retires(const Candidate&, const Evidence& ev) const {
  std::vector<std::string> out;
  for (const auto& part : parts_) {
    auto more = part.h->retires(part.c, ev);
    out.insert(out.end(), more.begin(), more.end());
  }
  return out;
}

Candidate Joint::candidate(const std::vector<double>& ranged) const {
  Candidate c = ic_;
  c.names.insert(c.names.end(), pc_.names.begin(), pc_.names.end());
  c.start.insert(c.start.end(), ranged.begin(), ranged.end());
  c.lo.insert(c.lo.end(), pc_.lo.begin(), pc_.lo.end());
  c.hi.insert(c.hi.end(), pc_.hi.begin(), pc_.hi.end());
  return c;
}

lang::ParamValues Joint::overrides(const Candidate&, const std::vector<double>& p) const {
  lang::ParamValues v = par_->overrides(pc_, tail(p));
  for (auto& [k, x] : inner_->overrides(ic_, head(p)))
    v.insert_or_assign(k, x);
  return v;
}

std::vector<std::vector<double>> Joint::restarts(const Candidate& c) const {
  std::vector<std::vector<double>> out = inner_->restarts(ic_);
  const std::vector<double> ranged = tail(c.start);
  for (auto& s : out)
    s.insert(s.end(), ranged.begin(), ranged.end());
  return out;
}

void Joint::extend(const Candidate&, const std::vector<double>& p, lang::NetworkSpec& spec) const {
  inner_->extend(ic_, head(p), spec);
}

bool Joint::corrects(const Candidate&) const {
  return inner_->corrects(ic_);
}

void Joint::correct(const Candidate&, const std::vector<double>& p, int node,
                    const std::vector<double>& times, std::vector<double>& sim) const {
  inner_->correct(ic_, head(p), node, times, sim);
}

std::string Joint::statement(const Candidate&, const std::vector<double>& p,
                             const Evidence& ev) const {
  return inner_->statement(ic_, head(p), ev) + "\n# fitted jointly with the ranged params:\n" +
         par_->statement(pc_, tail(p), ev);
}

CaseLines Joint::case_statements(const Candidate&, const std::vector<double>& p,
                                 const Evidence& ev) const {
  return inner_->case_statements(ic_, head(p), ev);
}

lang::ParamValues Joint::rewrites(const Candidate&, const std::vector<double>& p) const {
  return inner_->rewrites(ic_, head(p));
}

std::vector<std::string> Joint::retires(const Candidate&, const Evidence& ev) const {
  return inner_->retires(ic_, ev);
}

std::vector<double> Joint::head(const std::vector<double>& p) const {
  return {p.begin(), p.begin() + static_cast<long>(ic_.start.size())};
}

std::vector<double> Joint::tail(const std::vector<double>& p) const {
  return {p.begin() + static_cast<long>(ic_.start.size()), p.end()};
}

} // namespace thermnet::detail
