#pragma once
/// The diagnosis's evidence/fit engine (internal to kernel/diagnosis): the data and the baseline,
/// the screen's evidence, simulation of candidates on top of applied findings, fits with
/// validation folds (leave one case out, or each stretch of one case held back in turn) and the
/// gain of a candidate. What to refit and what to report is decided by the selection
/// (selection.hpp).

#include "kernel/diagnosis/composites.hpp"
#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/diagnosis/statistics.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <set>
#include <string>
#include <string_view>
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

/// The model candidates are compared with: the declared model plus the findings applied so far.
struct Base {
  std::vector<Applied> applied;   ///< applied findings, in order
  CaseSims raw;                   ///< simulated series of the model-side extensions (uncorrected)
  CaseSims sims;                  ///< with the measurement-side corrections: compared with data
  double sse_all = 0.0;           ///< SSE on all data, K^2
  double sse_test = 0.0;          ///< SSE on the held-out points of every fold, K^2
  StoredResiduals holdout_r;      ///< residuals on the held-out points of every fold, K
  std::vector<StoredResiduals> r; ///< residuals on all data, per measured series, K
  FitMetrics metrics;             ///< its fit
  bool at_floor = false;          ///< its error is measurement noise only
};

/// A hypothesis with one candidate (what the engine refits).
struct Entry {
  const Hypothesis* h = nullptr;     ///< hypothesis (possibly a Joint)
  Candidate c;                       ///< candidate
  const Hypothesis* own_h = nullptr; ///< the candidate's own hypothesis (the Joint's inner)
  Candidate own;                     ///< the candidate with its own parameters only
  std::string proxy; ///< a counterpart's: the site of the shortlisted candidate it stands beside
};

/// A refitted candidate: the finding and what the mechanism comparison needs.
struct Evaluated {
  Finding f;                       ///< the finding (empty values: the fit failed)
  std::vector<StoredResiduals> r;  ///< residuals on all data, per measured series
  double holdout_sse = 0.0;        ///< SSE on the held-out points of every fold
  StoredResiduals holdout_r;       ///< residuals on them (fold by fold, series order), K
  std::vector<double> holdout_rho; ///< their correlation (Refit::holdout_rho)
  bool degenerate = false;         ///< the fit is another kind's candidate (not reported)
};

/// What a candidate's refit computes (the costly part of Engine::evaluate()): all that processes
/// exchange when the refits are spread over them, the finding being made from it everywhere.
struct Refit {
  bool ok = false;                 ///< the fit and every validation fold succeeded
  bool moved = true;               ///< the all-data fit left its start (from some start)
  std::vector<double> p;           ///< fitted parameters (all data)
  std::vector<double> se;          ///< their standard errors (NaN when unknown)
  double sse = 0.0;                ///< SSE on all data, K^2
  double holdout_sse = 0.0;        ///< SSE on the held-out points of every fold, K^2
  StoredResiduals r;               ///< residuals on all data (measured rows, series by series), K
  StoredResiduals holdout_r;       ///< residuals on the held-out points of every fold, K
  std::vector<double> holdout_rho; ///< their positive_autocorrelation within the held-out segments
};

/// A refit as bytes, for the processes that did not compute it.
std::string pack_refit(const Refit& refit);

/// The refit pack_refit() wrote; throws std::runtime_error on a truncated buffer.
Refit unpack_refit(std::string_view bytes);

/// The evidence of one model's cases with data and the fits of candidates against it.
class Engine {
public:
  /// Loads the data of the cases (options.cases, or every case with data), simulates the declared
  /// model and builds the screen's evidence; throws DiagnosisError, lang::ModelError or
  /// lang::CsvError. `model` is kept by reference.
  Engine(const lang::Model& model, const DiagnosisOptions& options);

  /// The evidence at the declared model.
  const Evidence& evidence() const { return ev_; }
  /// The declared model as a base (the baseline).
  const Base& declared() const { return base0_; }
  /// Validation folds: cases held out whole (each alone, or in case_folds groups), or each
  /// stretch of a case split in time.
  std::size_t folds() const { return folds_.size(); }
  /// How the data are held out: "leave_one_case_out" (every case whole and alone), "case_folds"
  /// (every case whole, in the groups case_folds() names), "held_back_time" (one case, its
  /// stretches) or "cases_and_time" (cases held out whole, and the cases split_cases() names by
  /// their stretches).
  std::string validation() const;
  /// The cases validated by their stretches of time, though other cases exist: an event of theirs
  /// no other case has, which a fit to the other cases could not test.
  std::vector<std::string> split_cases() const;
  /// The cases of each fold that holds out several whole cases (empty when each is alone).
  std::vector<std::vector<std::string>> case_folds() const;
  /// Measured points, all data.
  std::size_t points() const { return all_rows_.count; }
  /// Measured points held out over every fold.
  std::size_t held_out_points() const { return n_test_; }
  /// Each fold's held-out points (the blocks of a base's or refit's holdout_r, in order).
  const std::vector<std::size_t>& fold_points() const { return fold_points_; }
  /// The held-out points (in the order of a base's or refit's holdout_r) as runs of consecutive
  /// samples of one series, their lengths.
  const std::vector<std::size_t>& holdout_segments() const { return segments_; }
  /// Residuals on all data per measured series (the order of Evaluated::r).
  std::vector<StoredResiduals> series_residuals(const CaseSims& sims) const;

  /// The declared model with findings applied at their values; `measured`: with its fit metrics
  /// and floor test too (a comparison that reads only the residuals goes without).
  Base make_base(std::vector<Applied> applied, bool measured = true) const;
  /// The screen's evidence on top of a base (a sensor found faulty is screened with its simulated
  /// temperature).
  Evidence evidence_at(const Base& base) const;
  /// Fits a candidate on top of a base on all data (the reported values) and in every validation
  /// fold, and measures its gain; a joint refit (many parameters) stops earlier.
  Evaluated evaluate(const Entry& e, const Base& base, bool joint = false) const;
  /// evaluate() of every entry: the refits spread over the processes (process_group.hpp) and
  /// their threads (options.threads); the same results whatever their numbers.
  std::vector<Evaluated> evaluate_all(const std::vector<Entry>& entries, const Base& base,
                                      bool joint = false) const;
  /// n ln((SSE_after + f n) / (SSE_before + f n)) + k ln n over all data (f: a small noise floor).
  double delta_bic(double sse_after, double sse_before, double k) const;
  /// The longest trend disagreement of the nodes in words (empty if none).
  std::string trend_words(const FitMetrics& m, const std::vector<std::string>& nodes) const;
  /// Per case: measured, baseline and `after` (if it applies findings) series of every node, and
  /// the steps of the findings `all` applies (the models with its first 1, 2, ... findings).
  std::vector<DiagnosisReport::Curves> curves(const Base& after, const Base& all) const;
  /// The Jacobian d(residual)/d(parameter) on all data of an entry's candidate on top of a base
  /// at p: from the cases' forward sensitivities and the corrections' derivatives (empty when the
  /// networks cannot integrate them), or (with `differences`) from central differences of
  /// simulations; for tests of the one against the other.
  Eigen::MatrixXd residual_jacobian(const Entry& e, const Base& base, const std::vector<double>& p,
                                    bool differences) const;
  /// The refit batches so far (consecutive ones on the same base kind merged), for the report.
  const std::vector<RefitBatch>& batches() const { return batches_; }

private:
  struct Fit {
    bool ok = false;
    bool moved = false; // some step was accepted
    std::vector<double> p;
    std::vector<double> se;
    double sse = 0.0;
    Eigen::MatrixXd J;     // residual Jacobian (working coordinates) at the last linearisation
    std::vector<double> r; // residuals at p
    CaseSims sims;         // the corrected simulation at p of the part's cases (empty: not kept)
  };

  // evidence.cpp
  void load_cases();
  void place_known_events();
  void simulate_baseline();
  void build_screen(CaseEvidence& ce, const RowMatrix& all,
                    const std::set<int>& distrusted = {}) const;
  // case_simulation.cpp
  void make_folds();
  /// Indexes each part's points (mask, count, sum of squares) and the held-out runs.
  void index_parts();
  bool case_used(std::size_t c, Part part) const;
  bool in_part(std::size_t c, std::size_t k, Part part) const;
  std::size_t stretch_of(std::size_t c, std::size_t k) const;
  CaseSims model_sims(const Hypothesis* h, const Candidate* c, const std::vector<double>& p,
                      Part part, const Base& base) const;
  void correct(const Hypothesis& h, const Candidate& c, const std::vector<double>& p,
               CaseSims& sims) const;
  CaseSims simulate(const Hypothesis* h, const Candidate* c, const std::vector<double>& p,
                    Part part, const Base& base) const;
  void residuals(const CaseSims& sims, Part part, std::vector<double>& r) const;
  /// The series' values at the part's measured points, in the residuals' order.
  void part_values(const CaseSims& sims, Part part, std::vector<double>& out) const;
  /// The part's measured points of sims in the residuals' order, less the data when asked.
  void gather(const CaseSims& sims, Part part, bool minus_measured, std::vector<double>& out) const;
  /// Whether sims holds every case the part uses (a simulation made for another part).
  bool covers(const CaseSims& sims, Part part) const;
  bool model_sensitivities(const Hypothesis& h, const Candidate& c, const std::vector<double>& p,
                           Part part, const Base& base, CaseSims& sims,
                           std::vector<CaseSims>& dsims) const;
  bool jacobian_residuals(const Hypothesis& h, const Candidate& c, const std::vector<double>& p,
                          Part part, const Base& base, std::vector<double>& r,
                          Eigen::MatrixXd& J) const;
  /// Whether each measured point (the order of Part{}'s residuals) is in the part.
  const std::vector<char>& rows_in(Part part) const;
  /// The total sum of squares of the part's measured values about their mean, K^2.
  double sst(Part part) const;
  // candidate_fit.cpp
  Fit fit(const Hypothesis& h, const Candidate& c, const std::vector<double>& start, Part part,
          const Base& base, int max_iter, double rtol, const Fit* warm = nullptr,
          bool std_errors = true) const;
  /// Sets f.se from its Jacobian (NaN left where the parameters are not all determined).
  void set_std_errors(const Candidate& c, Fit& f) const;
  // engine.cpp
  Refit refit(const Entry& e, const Base& base, bool joint) const;
  Fit fit_all_data(const Hypothesis& h, const Candidate& c, const Base& base, int max_iter,
                   double rtol) const;
  Evaluated evaluated(const Entry& e, const Base& base, Refit refit) const;
  bool validate(const Hypothesis& h, const Candidate& c, const Fit& all, const Base& base,
                int max_iter, double rtol, std::vector<double>& holdout_r) const;
  bool determined_in(const Candidate& c, const Fit& all, Part part) const;
  void measure_gain(Finding& f, const Base& base, double sse, double holdout_sse) const;
  template <class Work>
  void timed(const Base& base, bool joint, std::size_t refits, Work&& work) const;
  // fit_metrics.cpp
  FitMetrics metrics(const CaseSims& sims) const;
  bool at_floor(const FitMetrics& m) const;

  const lang::Model& model_;
  DiagnosisOptions opt_;
  Evidence ev_;
  std::vector<std::pair<double, double>> span_; // per case: first time and time span, s
  /// A validation fold: the cases of a group held out whole (stretch < 0), or a stretch of case c.
  struct Fold {
    std::size_t c = 0; ///< the case split in time, or the group's first case
    int stretch = -1;
  };
  std::vector<Fold> folds_;
  std::vector<std::size_t> group_; // per case held out whole: its group's fold (split: none)
  /// A part's measured points, found once (every residual gathers them).
  struct PartRows {
    std::vector<char> in;  ///< per measured point (Part{}'s order): in the part
    std::size_t count = 0; ///< points in the part
    double sst = 0.0;      ///< sum of squares of their values about their mean
  };
  PartRows all_rows_;                            // Part{}
  std::vector<PartRows> test_rows_, train_rows_; // per fold
  std::vector<std::size_t> case_row_;            // per case, its first point; then the total
  const PartRows& part_rows(Part part) const;
  std::size_t n_test_ = 0;                               // held-out points over every fold
  std::vector<std::size_t> fold_points_;                 // held-out points of each fold
  std::vector<std::size_t> segments_;                    // held-out runs, per fold and series
  Base base0_;                                           // the declared model
  mutable std::atomic<std::size_t> simulations_{0};      // case simulations run (every thread)
  mutable std::atomic<std::size_t> sensitivity_runs_{0}; // of those, with sensitivities
  mutable std::vector<RefitBatch> batches_;              // timing of the refits (main thread only)
};

/// Simulates a case at the measured times: temperatures of every node (spec order), K; with
/// `measured`, also the simulated value of each of its series into `series` (a node's
/// temperature, or its sensor's reading).
RowMatrix simulate_case(lang::NetworkSpec spec, const std::vector<double>& times,
                        const MeasuredData* measured = nullptr,
                        std::vector<Series>* series = nullptr);

/// Simulates a case at the measured times: the simulated value of each of the data's series only
/// (what a refit compares; the other nodes' temperatures are not kept).
std::vector<Series> simulate_series(lang::NetworkSpec spec, const MeasuredData& measured);

/// The signature of the error a model leaves (sims: its series at the measured times, rmse its
/// RMSE): residual_signature.cpp; `remains` is left for the caller to decide.
StructuralError residual_signature(const Evidence& ev, const CaseSims& sims, double rmse);

/// Two candidates at the same site with the same mechanism.
bool same_candidate(const Candidate& a, const Candidate& b);
/// A typical size of parameter j at p: |p[j]|, or 1e-3 of its box near 0 (1 where neither is a
/// positive finite number); the steps that difference or move it are fractions of it.
double parameter_size(const Candidate& c, const std::vector<double>& p, std::size_t j);

/// Sets what a finding writes (statements, case lines, rewritten params): its hypothesis's text
/// for the candidate at p.
void write_extension(Finding& f, const Hypothesis& h, const Candidate& c,
                     const std::vector<double>& p, const Evidence& ev);

/// Sets which of a finding's values p ended on a bound of the candidate's box (at_bounds).
void mark_bounds(Finding& f, const Candidate& c, const std::vector<double>& p);

} // namespace thermnet::detail
