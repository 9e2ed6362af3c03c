#pragma once
/// Model diagnosis: what the simulation gets wrong, which extension explains it, and the gain
/// (shared/spec/diagnose.md). The engine measures the baseline, screens every candidate of every
/// hypothesis plugin on the unexplained heat flows, refits the best by simulation, validates them
/// on data not used for the fit (leave one case out, or a held-back stretch of time), ranks them
/// and selects findings greedily (each next one given the ones above).

#include "kernel/diagnosis/hypothesis.hpp"
#include "kernel/diagnosis/likelihood_findings.hpp"
#include "lang/model.hpp"

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace thermnet {

/// What a diagnosis is doing, for a progress display.
struct DiagnosisProgress {
  std::string stage;     ///< in words, e.g. "refitting candidates"
  std::size_t done = 0;  ///< refits of the stage done
  std::size_t total = 0; ///< refits of the stage (0: a stage without a count)
};

/// How to diagnose.
struct DiagnosisOptions {
  std::vector<std::string> cases; ///< cases to use (empty: every case with data)
  int threads = 0;                ///< worker threads (0: all cores)
  std::size_t top = 5;            ///< most findings reported
  std::size_t refits = 6;         ///< model-side candidates refitted by simulation (plus the
                                  ///< best of each kind)
  std::size_t time_folds = 3;     ///< with one case: equal stretches of its time span, each held
                                  ///< back once for validation
  /// most folds of cases held out whole: with more cases, case i of them joins fold i mod this
  /// (5-fold instead of leave-one-case-out, whose cost grows with the square of the cases)
  std::size_t case_folds = 5;
  /// known events (a lid opened), for event_loss candidates: as read_events() gives them (a log's
  /// UNIX times are placed in each case by its data file's first time)
  std::vector<EventWindow> events;
  std::string events_path; ///< the file the events come from, named in errors
  /// "output-error" (the default: simulation residuals, held-out validation) or "prediction"
  /// (one-step-ahead predictions of a Kalman filter, likelihood-ratio tests)
  std::string criterion = "output-error";
  double initial_sd = 1.0; ///< prediction: initial states' standard deviation, K
  /// The practical floor: no finding whose largest local gain (the RMS error over 10 consecutive
  /// samples of a series, lowered at most) is below this, K.
  double min_gain = 0.05;
  /// output-error: the refits' Jacobians from the cases' forward sensitivities (CVODES) instead of
  /// forward differences of simulations (fewer simulations; near-tied fits may end elsewhere)
  bool sensitivities = false;
  /// Told what the diagnosis is doing (at each stage and after each refit; from worker threads
  /// too, never two calls at once); empty: nothing is told.
  std::function<void(const DiagnosisProgress&)> progress;
};

/// How far the simulation is off for one node (one case or all cases together).
struct NodeMetrics {
  double rmse = 0.0;                   ///< K
  double bias = 0.0;                   ///< mean(sim - meas), K
  double max_error = 0.0;              ///< largest |sim - meas|, K (signed: sim - meas)
  double max_error_time = 0.0;         ///< when, s
  std::string max_error_case;          ///< in which case
  double trend_mismatch_s = 0.0;       ///< time where measured and simulated slopes disagree, s
  double longest_mismatch_s = 0.0;     ///< longest such stretch, s
  double longest_mismatch_start = 0.0; ///< its start, s
  std::string longest_mismatch_case;   ///< its case
  bool measured_rising = false;        ///< over that stretch: measured rises (and simulated falls)
  std::size_t points = 0;              ///< compared points
  double window_rmse = 0.0;            ///< largest RMS error over consecutive samples, K
};

/// Fit of a whole model to the data.
struct FitMetrics {
  double rmse = 0.0;                                               ///< K
  double r2 = 0.0;                                                 ///< 1 - SSE / SST
  std::map<std::string, NodeMetrics> nodes;                        ///< per node, every case
  std::map<std::string, std::map<std::string, NodeMetrics>> cases; ///< per case, per node
  /// The largest window_rmse of any node, K.
  double worst_window_rmse() const;
};

/// A candidate that fits the data as well as a finding's own (within the held-out test's spread).
struct Rival {
  Candidate candidate;                ///< what it is
  std::vector<double> values;         ///< its fitted parameters (candidate.names)
  double rmse_after = 0.0;            ///< K, all data
  double validation_rmse_after = 0.0; ///< K, held-out data
  double z = 0.0;                     ///< how much better the finding predicts held-out data (z)
};

/// One ranked finding.
struct Finding {
  int rank = 0;                        ///< 1 = best
  Candidate candidate;                 ///< what it is
  std::vector<double> values;          ///< fitted extra parameters (candidate.names)
  std::vector<double> std_errors;      ///< their standard errors (NaN when unknown)
  std::string statement;               ///< netlist statements that add it (top level)
  CaseLines case_statements;           ///< lines that complete it inside case blocks, by case
  lang::ParamValues param_rewrites;    ///< params --write rewrites instead (name -> SI value)
  std::vector<std::string> retired;    ///< elements whose declarations --write comments out
  std::string evidence;                ///< the evidence in words
  bool mechanism_identified = true;    ///< the data tell the kind's mechanisms apart
  std::string mechanism_note;          ///< e.g. "linear and radiation fit equally; kept linear"
  double mechanism_z = 0.0;            ///< SSE difference of the mechanisms / its spread
  int given = 0;                       ///< findings applied before this one (ranks 1..given)
  double rmse_before = 0.0;            ///< K, all data
  double rmse_after = 0.0;             ///< K, all data (fitted)
  double r2_before = 0.0;              ///< all data
  double r2_after = 0.0;               ///< all data
  double validation_rmse_before = 0.0; ///< K, held-out data (every fold's held-out points)
  double validation_rmse_after = 0.0;  ///< K, held-out data, each fold fitted without them
  double validation_r2_before = 0.0;   ///< held-out data
  double validation_r2_after = 0.0;    ///< held-out data
  double delta_bic = 0.0;              ///< BIC after - BIC before (negative: better)
  bool significant = false;            ///< passes the significance rule
  /// The refit never left its starting points (no step lowered the error from any of them): the
  /// fit failed, which says nothing of the candidate's gain
  bool fit_failed = false;
  /// How the node it adds starts in each case, in words (empty: it adds none)
  std::string start;
  double holdout_z = 0.0; ///< held-out gain over its reference fit, z
  /// The smallest relative drop of the held-out RMS error over the validation blocks against its
  /// reference fits (0.3: every block predicted with 30 % less error)
  double block_gain = 0.0;
  /// The largest drop of the RMS error over 10 consecutive samples of one series against its
  /// reference fit, K (the practical floor's measure)
  double window_gain = 0.0;
  std::map<std::string, std::string> at_bounds; ///< fitted values on a bound: name -> lower/upper
  std::vector<Rival> rivals;                    ///< candidates that fit as well (the ambiguity set)
  std::string separate_by;                  ///< what measurement would separate it from its rivals
  std::optional<LikelihoodTest> likelihood; ///< prediction criterion: its likelihood-ratio test
};

/// The signature of the error left after the findings, when it is far above the noise floor: what
/// a model error no finding kind names looks like (its autocorrelation, its periodogram, its
/// correlation with each input at each lag).
struct StructuralError {
  bool remains = false;     ///< the error left is 2x the noise floor or more, and >= --min-gain
  double rmse = 0.0;        ///< K, after the findings
  double independent = 0.0; ///< independent points the residuals hold (n over their AR(1) time)
  /// (lag s, autocorrelation) at lags of 1, 2, 5, 10, 20, 50... samples (below half a case)
  std::vector<std::pair<double, double>> autocorrelation;
  double period_s = 0.0;     ///< the period of the sinusoid that explains most of the residual, s
  double period_share = 0.0; ///< the share of the residual's sum of squares it explains
  /// One input's largest correlation with the residual.
  struct Input {
    std::string name;   ///< a boundary's temperature (its name) or a source's power (ELEMENT.P)
    double lag_s = 0.0; ///< the residual follows the input this much later, s
    double r = 0.0;     ///< the correlation at that lag
  };
  std::vector<Input> inputs; ///< by falling |r|
};

/// Where a diagnosis spent its time: a batch of candidate refits (the costly part); consecutive
/// batches of the same kind on the same base are merged.
struct RefitBatch {
  /// findings applied to the base model the candidates are fitted on (a joint refit of a later
  /// step carries the applied findings in its candidate and fits on the declared model: 0)
  std::size_t base_findings = 0;
  bool joint = false;     ///< refitted jointly with the ranged params
  std::size_t refits = 0; ///< candidates refitted (each on all data plus every validation fold)
  std::size_t simulations = 0; ///< case simulations the refits ran (in this process)
  /// of those, the ones that integrated parameter sensitivities (a Jacobian with the residuals)
  std::size_t sensitivity_runs = 0;
  /// prediction criterion: the likelihoods evaluated (each filters every case once)
  std::size_t likelihoods = 0;
  double wall_s = 0.0; ///< wall time, s
  double cpu_s = 0.0;  ///< CPU time of the process (every thread), s
};

/// The outcome of a diagnosis.
struct DiagnosisReport {
  std::string model;                 ///< model path
  std::vector<std::string> cases;    ///< cases used
  double noise_floor = 0.0;          ///< estimated measurement noise, K
  bool at_noise_floor = false;       ///< baseline error is measurement noise only
  double min_gain = 0.0;             ///< the practical floor used (DiagnosisOptions::min_gain), K
  StructuralError structural;        ///< what the error left looks like
  FitMetrics baseline;               ///< the model as declared
  std::vector<Finding> findings;     ///< significant findings, best first, each given the previous
  std::vector<Finding> alternatives; ///< significant alone, but explained by a finding above
  std::vector<Finding> rejected;     ///< refitted candidates that were not significant
  std::size_t screened = 0;          ///< candidates screened
  std::size_t refitted = 0;          ///< candidates refitted by simulation
  std::string criterion = "output-error";      ///< the criterion used (DiagnosisOptions::criterion)
  std::optional<PredictionSummary> prediction; ///< prediction criterion: likelihoods, whiteness
  /// "leave_one_case_out", "case_folds", "held_back_time" or "cases_and_time"
  std::string validation;
  std::vector<std::string> split_cases; ///< with "cases_and_time": the cases held out by stretches
  /// the cases of each fold that holds out more than one whole case (empty: each case alone)
  std::vector<std::vector<std::string>> case_folds;
  std::size_t folds = 0;     ///< validation folds
  double wall_s = 0.0;       ///< wall time, s
  double cpu_s = 0.0;        ///< CPU time of the process (every thread), s
  double setup_wall_s = 0.0; ///< wall time of loading the data, the baseline and the heat flows, s
  std::vector<RefitBatch> batches; ///< the refit batches, in order
  /// Per case: times, and per measured node: measured, baseline and best-finding series (K).
  struct Curves {
    std::string case_name;                               ///< case
    std::vector<double> times;                           ///< s
    std::map<std::string, std::vector<double>> measured; ///< node -> K
    std::map<std::string, std::vector<double>> before;   ///< node -> K
    std::map<std::string, std::vector<double>> after; ///< node -> K (best finding; empty if none)
    /// node -> K with findings 1..k applied, for k = 1 .. findings (at their final values): each
    /// finding's own step goes from steps[k - 2] (`before` for k = 1) to steps[k - 1]
    std::vector<std::map<std::string, std::vector<double>>> steps;
  };
  std::vector<Curves> curves; ///< for plots
};

/// A diagnosis that cannot run (no case with data, unknown case).
struct DiagnosisError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Diagnoses a model against the measured data of its cases; throws DiagnosisError,
/// lang::ModelError or lang::CsvError on bad input.
DiagnosisReport diagnose(const lang::Model& model, const DiagnosisOptions& options = {});

/// Noise standard deviation of one series from its second differences (robust: median absolute
/// deviation), K; NaN values are skipped; 0 when too short.
double estimate_noise(const std::vector<double>& values);

/// Local quadratic (Savitzky-Golay-like) smoothing on possibly uneven times: value and slope at
/// every sample from the 2*half+1 neighbours; NaN samples are skipped.
void smooth_series(const std::vector<double>& times, const std::vector<double>& values, int half,
                   std::vector<double>& smoothed, std::vector<double>& slope);

} // namespace thermnet
