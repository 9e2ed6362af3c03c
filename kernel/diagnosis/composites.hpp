#pragma once
/// The hypotheses the diagnosis engine composes from the plugins' ones (internal to
/// kernel/diagnosis): applied findings with a free candidate on top, a candidate refitted together
/// with the ranged params, and several candidates refitted together.

#include "kernel/diagnosis/hypothesis.hpp"

#include <vector>

namespace thermnet::detail {

/// A finding applied with its fitted values held fixed.
struct Applied {
  const Hypothesis* h = nullptr; ///< its hypothesis
  Candidate c;                   ///< its candidate
  std::vector<double> p;         ///< its values
};

/// A free candidate on top of applied findings (fixed values), as one hypothesis; with no free
/// hypothesis it is the applied findings alone.
class Stack final : public Hypothesis {
public:
  /// Applied findings plus (optionally) a free candidate.
  Stack(const std::vector<Applied>* applied, const Hypothesis* free, const Candidate* fc)
      : applied_(applied), free_(free), fc_(fc) {}
  std::vector<Candidate> propose(const Evidence&) const override { return {}; }
  lang::ParamValues overrides(const Candidate&, const std::vector<double>& p) const override;
  void extend(const Candidate&, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override;
  bool corrects(const Candidate&) const override;
  void correct(const Candidate&, const std::vector<double>& p, int node,
               const std::vector<double>& times, std::vector<double>& sim) const override;
  std::string statement(const Candidate&, const std::vector<double>& p,
                        const Evidence& ev) const override;
  CaseLines case_statements(const Candidate&, const std::vector<double>& p,
                            const Evidence& ev) const override;
  lang::ParamValues rewrites(const Candidate&, const std::vector<double>& p) const override;
  std::vector<std::string> retires(const Candidate&, const Evidence& ev) const override;
  bool degenerate(const Candidate&, const std::vector<double>& p) const override {
    return free_ && free_->degenerate(*fc_, p);
  }
  std::vector<std::vector<double>> restarts(const Candidate&) const override {
    return free_ ? free_->restarts(*fc_) : std::vector<std::vector<double>>{};
  }

private:
  const std::vector<Applied>* applied_;
  const Hypothesis* free_;
  const Candidate* fc_;
};

/// A model-side candidate refitted together with the model's ranged params (the joint refit):
/// parameters = the candidate's own, then every ranged param (the recalibrating candidate's).
class Joint final : public Hypothesis {
public:
  /// The inner candidate of `inner` joined with the recalibrating candidate `pc` of `par`.
  Joint(const Hypothesis* inner, Candidate ic, const Hypothesis* par, Candidate pc)
      : inner_(inner), ic_(std::move(ic)), par_(par), pc_(std::move(pc)) {}
  /// The joint candidate: the inner one with the ranged params appended (started at `ranged`).
  Candidate candidate(const std::vector<double>& ranged) const;
  std::vector<Candidate> propose(const Evidence&) const override { return {}; }
  /// True: the ranged params are refitted with the candidate.
  bool recalibrates() const override { return true; }
  bool reroutes() const override { return inner_->reroutes(); }
  bool degenerate(const Candidate&, const std::vector<double>& p) const override {
    return inner_->degenerate(ic_, head(p));
  }
  /// The inner candidate's restarts, the ranged params at c's start.
  std::vector<std::vector<double>> restarts(const Candidate& c) const override;
  lang::ParamValues overrides(const Candidate&, const std::vector<double>& p) const override;
  void extend(const Candidate&, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override;
  bool corrects(const Candidate&) const override;
  void correct(const Candidate&, const std::vector<double>& p, int node,
               const std::vector<double>& times, std::vector<double>& sim) const override;
  std::string statement(const Candidate&, const std::vector<double>& p,
                        const Evidence& ev) const override;
  CaseLines case_statements(const Candidate&, const std::vector<double>& p,
                            const Evidence& ev) const override;
  lang::ParamValues rewrites(const Candidate&, const std::vector<double>& p) const override;
  std::vector<std::string> retires(const Candidate&, const Evidence& ev) const override;

private:
  std::vector<double> head(const std::vector<double>& p) const;
  std::vector<double> tail(const std::vector<double>& p) const;
  const Hypothesis* inner_;
  Candidate ic_;
  const Hypothesis* par_;
  Candidate pc_;
};

/// Several candidates refitted together (the findings selected so far, re-estimated at each step
/// of the forward selection): the parameters are theirs, concatenated in order.
class Compose final : public Hypothesis {
public:
  /// The parts, each a hypothesis with its candidate.
  explicit Compose(std::vector<Applied> parts) : parts_(std::move(parts)) {}
  /// The composed candidate (started at the parts' values).
  Candidate candidate() const;
  /// The parameters of part i within p.
  std::vector<double> slice(const std::vector<double>& p, std::size_t i) const;
  std::vector<Candidate> propose(const Evidence&) const override { return {}; }
  /// The last part (the candidate a step adds on top of the findings) is another kind's.
  bool degenerate(const Candidate&, const std::vector<double>& p) const override {
    return !parts_.empty() &&
           parts_.back().h->degenerate(parts_.back().c, slice(p, parts_.size() - 1));
  }
  lang::ParamValues overrides(const Candidate&, const std::vector<double>& p) const override;
  void extend(const Candidate&, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override;
  bool corrects(const Candidate&) const override;
  void correct(const Candidate&, const std::vector<double>& p, int node,
               const std::vector<double>& times, std::vector<double>& sim) const override;
  std::string statement(const Candidate&, const std::vector<double>& p,
                        const Evidence& ev) const override;
  CaseLines case_statements(const Candidate&, const std::vector<double>& p,
                            const Evidence& ev) const override;
  lang::ParamValues rewrites(const Candidate&, const std::vector<double>& p) const override;
  std::vector<std::string> retires(const Candidate&, const Evidence& ev) const override;

private:
  std::vector<Applied> parts_;
};

} // namespace thermnet::detail
