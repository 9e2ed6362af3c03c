#pragma once
/// The diagnosis engine (internal to kernel/diagnosis*.cpp): evidence, simulation of candidates,
/// fits with validation folds (leave one case out, or a held-back stretch of time), the screen's
/// shortlist and the greedy forward selection of findings.

#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/diagnosis/statistics.hpp"

#include <Eigen/Dense>

#include <memory>
#include <set>
#include <string>
#include <vector>

namespace thermnet::detail {

using Series = std::vector<double>;
/// sims[case][series][k]: simulated temperature of each measured series at the measured times
/// (an unused case of a Part has no series).
using CaseSims = std::vector<std::vector<Series>>;

/// Which data points: all, or the fitted (train) or held-out (test) points of a validation fold.
struct Part {
  enum What { all, train, test } what = all; ///< which points
  std::size_t fold = 0;                      ///< fold (the held-out case when leaving cases out)
};

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
  void correct(const Candidate&, const std::vector<double>& p, int node,
               const std::vector<double>& times, std::vector<double>& sim) const override;
  std::string statement(const Candidate&, const std::vector<double>& p,
                        const Evidence& ev) const override;
  CaseLines case_statements(const Candidate&, const std::vector<double>& p,
                            const Evidence& ev) const override;
  lang::ParamValues rewrites(const Candidate&, const std::vector<double>& p) const override;

private:
  const std::vector<Applied>* applied_;
  const Hypothesis* free_;
  const Candidate* fc_;
};

/// A model-side candidate refitted together with the model's ranged params (the joint refit):
/// parameters = the candidate's own, then every ranged param (the `parameter` candidate's).
class Joint final : public Hypothesis {
public:
  /// The inner candidate of `inner` joined with the `parameter` candidate `pc` of `par`.
  Joint(const Hypothesis* inner, Candidate ic, const Hypothesis* par, Candidate pc)
      : inner_(inner), ic_(std::move(ic)), par_(par), pc_(std::move(pc)) {}
  /// The joint candidate: the inner one with the ranged params appended (started at `ranged`).
  Candidate candidate(const std::vector<double>& ranged) const;
  /// The inner hypothesis and candidate (the candidate's own parameters only).
  const Hypothesis* inner() const { return inner_; }
  /// The inner candidate.
  const Candidate& inner_candidate() const { return ic_; }
  std::vector<Candidate> propose(const Evidence&) const override { return {}; }
  /// True: the ranged params are refitted with the candidate.
  bool recalibrates() const override { return true; }
  lang::ParamValues overrides(const Candidate&, const std::vector<double>& p) const override;
  void extend(const Candidate&, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override;
  void correct(const Candidate&, const std::vector<double>& p, int node,
               const std::vector<double>& times, std::vector<double>& sim) const override;
  std::string statement(const Candidate&, const std::vector<double>& p,
                        const Evidence& ev) const override;
  CaseLines case_statements(const Candidate&, const std::vector<double>& p,
                            const Evidence& ev) const override;
  lang::ParamValues rewrites(const Candidate&, const std::vector<double>& p) const override;

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
  lang::ParamValues overrides(const Candidate&, const std::vector<double>& p) const override;
  void extend(const Candidate&, const std::vector<double>& p,
              lang::NetworkSpec& spec) const override;
  void correct(const Candidate&, const std::vector<double>& p, int node,
               const std::vector<double>& times, std::vector<double>& sim) const override;
  std::string statement(const Candidate&, const std::vector<double>& p,
                        const Evidence& ev) const override;
  CaseLines case_statements(const Candidate&, const std::vector<double>& p,
                            const Evidence& ev) const override;
  lang::ParamValues rewrites(const Candidate&, const std::vector<double>& p) const override;

private:
  std::vector<Applied> parts_;
};

/// The model candidates are compared with: the declared model plus the findings applied so far.
struct Base {
  std::vector<Applied> applied; ///< applied findings, in order
  CaseSims raw;                 ///< simulated series of the model-side extensions (uncorrected)
  CaseSims sims;                ///< with the measurement-side corrections: compared with data
  double sse_all = 0.0;         ///< SSE on all data, K^2
  double sse_test = 0.0;        ///< SSE on the held-out points of every fold, K^2
  FitMetrics metrics;           ///< its fit
  bool at_floor = false;        ///< its error is measurement noise only
};

/// A hypothesis with one candidate (what the engine refits).
struct Entry {
  const Hypothesis* h = nullptr;     ///< hypothesis (possibly a Joint)
  Candidate c;                       ///< candidate
  const Hypothesis* own_h = nullptr; ///< the candidate's own hypothesis (the Joint's inner)
  Candidate own;                     ///< the candidate with its own parameters only
};

/// A refitted candidate: the finding and what the mechanism comparison needs.
struct Evaluated {
  Finding f;                          ///< the finding (empty values: the fit failed)
  std::vector<std::vector<double>> r; ///< residuals on all data, per measured series
  double holdout_sse = 0.0;           ///< SSE on the held-out points of every fold
};

/// The diagnosis of one model.
class Engine {
public:
  /// An engine for `model` (kept by reference) with the options.
  Engine(const lang::Model& model, const DiagnosisOptions& opt) : model_(model), opt_(opt) {}
  /// Runs the whole diagnosis.
  DiagnosisReport run();

private:
  struct Fit {
    bool ok = false;
    std::vector<double> p;
    std::vector<double> se;
    double sse = 0.0;
    Eigen::MatrixXd J;     // residual Jacobian (working coordinates) at the last linearisation
    std::vector<double> r; // residuals at p
  };

  // diagnosis_engine.cpp
  void collect_evidence();
  void build_screen(CaseEvidence& ce, const std::vector<std::vector<double>>& all,
                    double& screen_total, const std::set<int>& distrusted = {}) const;
  std::size_t folds() const { return loco_ ? ev_.cases.size() : 1; }
  bool case_used(std::size_t c, Part part) const;
  bool in_part(std::size_t c, std::size_t k, Part part) const;
  CaseSims model_sims(const Hypothesis* h, const Candidate* c, const std::vector<double>& p,
                      Part part, const Base& base) const;
  void correct(const Hypothesis& h, const Candidate& c, const std::vector<double>& p,
               CaseSims& sims) const;
  CaseSims simulate(const Hypothesis* h, const Candidate* c, const std::vector<double>& p,
                    Part part, const Base& base) const;
  void residuals(const CaseSims& sims, Part part, std::vector<double>& r) const;
  std::vector<char> rows_in(Part part) const;
  double sst(Part part) const;
  Fit fit(const Hypothesis& h, const Candidate& c, const std::vector<double>& start, Part part,
          const Base& base, int max_iter, double rtol, const Fit* warm = nullptr) const;
  FitMetrics metrics(const CaseSims& sims) const;
  bool at_floor(const FitMetrics& m) const;
  Base make_base(std::vector<Applied> applied) const;
  Evidence evidence_at(const Base& base) const;
  Evaluated evaluate(const Entry& e, const Base& base, bool joint = false) const;
  std::string trend_words(const FitMetrics& m, const std::vector<std::string>& nodes) const;

  // diagnosis_select.cpp
  std::vector<Entry> propose(const Evidence& ev) const;
  std::vector<std::size_t> shortlist(const std::vector<Entry>& side, const Evidence& ev,
                                     std::size_t sites) const;
  std::vector<Evaluated> evaluate_all(const std::vector<Entry>& entries, const Base& base,
                                      bool joint = false) const;
  void judge(std::vector<Evaluated>& res) const;
  void merge_mechanisms(const std::vector<Entry>& entries, std::vector<Evaluated>& res) const;
  double score(const Finding& f) const;
  std::vector<std::size_t> ranked(const std::vector<Evaluated>& res) const;
  void add_curves(DiagnosisReport& rep, const Base& after) const;

  const lang::Model& model_;
  DiagnosisOptions opt_;
  Evidence ev_;
  std::vector<std::unique_ptr<Hypothesis>> hyps_;
  std::vector<double> split_; // per case: first held-back time (time-split validation)
  bool loco_ = false;         // leave one case out (>= 2 cases)
  std::size_t n_all_ = 0, n_test_ = 0;
  Base base0_; // the declared model
};

/// Two candidates at the same site with the same mechanism.
bool same_candidate(const Candidate& a, const Candidate& b);

/// Sets what a finding writes (statements, case lines, rewritten params): its hypothesis's text
/// for the candidate at p.
void write_extension(Finding& f, const Hypothesis& h, const Candidate& c,
                     const std::vector<double>& p, const Evidence& ev);

} // namespace thermnet::detail
