#pragma once
/// The diagnosis's decisions (internal to kernel/diagnosis), on top of the evidence/fit engine:
/// which candidates are refitted (the screen's shortlist, widened when the screen is a poor
/// guide), the joint refit with the ranged params, significance, one finding per site, ranking,
/// and the greedy forward selection of findings.

#include "kernel/diagnosis/engine.hpp"
#include "kernel/diagnosis/statistics.hpp"

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace thermnet::detail {

/// ΔBIC below which a fit beats its reference (very strong evidence on the Kass-Raftery scale).
constexpr double kSignificantBic = -10.0;

/// Where a candidate acts (a link's two mechanisms are one site).
std::string site(const Candidate& c);

/// Distinct sites in the order of the entries (the screen's order).
std::vector<std::string> site_order(const std::vector<Entry>& side);

/// True when a candidate is refitted as a model extension and compared by its screen score.
bool model_side(const Entry& e);

/// Indices into `entries` of the candidates of c's kind (either mechanism) that name, in place of
/// one of its unmeasured nodes, a boundary an element links that node to.
std::vector<std::size_t> boundary_exchanges(const std::vector<Entry>& entries, const Evidence& ev,
                                            const Candidate& c);

/// Indices into `entries` of the candidates of c's kind (either mechanism) that name, in place of
/// one of its boundaries, a node an element links to it (measured nodes first, 6 nodes at most).
std::vector<std::size_t> tied_node_exchanges(const std::vector<Entry>& entries, const Evidence& ev,
                                             const Candidate& c);

/// Indices into `entries` of the links of c's mechanism that name, in place of one end of the link
/// c, a node an element links to that end (measured nodes first, 6 at most per end).
std::vector<std::size_t> neighbour_exchanges(const std::vector<Entry>& entries, const Evidence& ev,
                                             const Candidate& c);

/// The counterparts among entries[beside] to refit: those whose proxy (`Entry::proxy`) is the site
/// of an entries[refitted] whose refit (res, same indices) failed, or has a ΔBIC below
/// reference_bic + kSignificantBic and an RMSE among the `best` sites of its kind that do, and
/// those whose proxy is none of their sites.
std::vector<std::size_t> beside_gaining(const std::vector<Entry>& entries,
                                        const std::vector<std::size_t>& beside,
                                        const std::vector<Evaluated>& res,
                                        const std::vector<std::size_t>& refitted,
                                        double reference_bic, std::size_t best);

/// Records on `keep` how its mechanism compared with the other one (`drop`); `mechanisms` are its
/// kind's, in order.
void note_mechanism(Finding& keep, const Finding& drop, const FitComparison& cmp,
                    const std::vector<std::string>& mechanisms);

/// The held-out RMS error a candidate must cut in every validation block (each fold's held-out
/// data), as a fraction, for its gain to count as confirmed whatever the residuals' correlation.
constexpr double kConfirmingBlockGain = 0.3;

/// Validation blocks a confirmation needs at least (with fewer, the z test alone decides).
constexpr std::size_t kConfirmingBlocks = 3;

/// A candidate's test against one reference fit: the held-out gain's z and the largest local gain.
struct Comparison {
  double z = 0.0;    ///< held-out gain over its spread (holdout_gain_z)
  double gain = 0.0; ///< largest gain over a window (largest_window_gain), K
  /// The smallest drop of the held-out RMS error over the validation blocks (worst_block_gain)
  double block_gain = 0.0;
  /// Every block (at least kConfirmingBlocks) gains kConfirmingBlockGain or more
  bool confirmed = false;
};

/// The screen's candidates: model-side ones by falling screen score, and the others (always
/// refitted), in proposal order.
struct Screened {
  std::vector<Entry> side;   ///< model-side, best screen score first
  std::vector<Entry> others; ///< measurement-side and recalibrating
};

/// The selection of findings from every registered hypothesis.
class Selection {
public:
  /// A selection over the engine's evidence (both kept by reference).
  Selection(const Engine& engine, const DiagnosisOptions& options);
  /// Screens, refits, judges and selects: fills the report's findings, alternatives, rejected
  /// and counts; returns the base with the best finding applied (the declared one if none), and
  /// in `last` the base with every finding applied.
  Base run(DiagnosisReport& rep, Base& last);

private:
  // The stages, in order (selection.cpp, joint_refit.cpp, tied_variants.cpp,
  // forward_selection.cpp).
  void refit_shortlist(DiagnosisReport& rep);
  void widen(std::size_t sites, std::set<std::size_t>& taken);
  /// The index in chosen_ of the ranged params' recalibration when refitting them alone is
  /// significant (better on all data by the information criterion), else chosen_.size().
  std::size_t significant_recalibration() const;
  std::size_t joint_refit(DiagnosisReport& rep);
  void add_recalibrated_shortlist(const Base& recalibrated);
  void refit_jointly(std::size_t recal, const std::vector<double>& ranged, const Base* recalibrated,
                     DiagnosisReport& rep);
  /// Refits chosen_[todo] jointly with the ranged params; each success replaces its result.
  void refit_batch(const std::vector<std::size_t>& todo, std::size_t recal,
                   const std::vector<double>& ranged, DiagnosisReport& rep);
  Entry joint_entry(const Entry& e, std::size_t recal, const std::vector<double>& ranged);
  void note_joint(Finding& f, std::size_t recal) const;
  void rank_first(std::size_t recal);
  bool refit_tied_variants(std::size_t recal, DiagnosisReport& rep);
  Base select_forward(DiagnosisReport& rep, Base& last);
  /// The refits of `next` on `base`: every candidate but the counterparts, then the counterparts
  /// beside a proxy that gains (beside_gaining); the others stay unfitted (no values).
  std::vector<Evaluated> evaluate_next(const std::vector<Entry>& next, const Base& base,
                                       DiagnosisReport& rep) const;
  std::vector<Entry> next_entries(const Base& base, const std::vector<Applied>& applied,
                                  bool params_applied) const;
  std::size_t rerank_jointly(const std::vector<Applied>& applied, const Base& base,
                             const std::vector<Entry>& next, std::vector<Evaluated>& nres) const;
  bool reestimate(std::vector<Applied>& applied, Finding f, DiagnosisReport& rep,
                  StoredResiduals& holdout_r) const;
  void redecide_mechanisms(std::vector<Applied>& applied, const Compose& all, Evaluated& joint,
                           DiagnosisReport& rep) const;
  void finish(DiagnosisReport& rep);
  /// Marks each jointly refitted candidate of `passed` not significant unless it beats, on held-out
  /// data, its own fitted params without it (`recal`: the recalibrating candidate; z_min: the
  /// step's threshold); the params' models are simulated in parallel.
  void against_own_params(const std::vector<std::size_t>& passed, std::size_t recal, double z_min);
  /// A refit's test against its own params alone, kept for the next ranking (the same refit is
  /// ranked again after the tied variants): its values and held-out SSE, and the test (none when
  /// those params alone could not be simulated).
  struct OwnParamsTest {
    std::vector<double> values;
    double holdout_sse = 0.0;
    std::optional<Comparison> cmp;
  };

  // shortlist.cpp
  std::vector<Entry> propose(const Evidence& ev) const;
  Screened screen(const Evidence& ev) const;
  std::vector<std::size_t> shortlist(const std::vector<Entry>& side, const Evidence& ev,
                                     std::size_t sites) const;
  std::vector<Entry> shortlisted(const std::vector<Entry>& side, const Evidence& ev,
                                 std::size_t sites, std::set<std::size_t>* taken) const;
  // judgement.cpp
  void judge(std::vector<Evaluated>& res, const Base& reference) const;
  /// The test of e against one reference fit (its held-out and all-data residuals).
  Comparison compare_to(const Evaluated& e, const StoredResiduals& holdout_r,
                        const std::vector<StoredResiduals>& r) const;
  /// Applies a test to e: the smallest z and gain are kept; below z_min or the least gain, e is
  /// not significant.
  void judge_against(Evaluated& e, const Comparison& cmp, double z_min) const;
  static double threshold(const std::vector<Evaluated>& res);
  void add_rivals(Finding& f, std::size_t best, const std::vector<Entry>& entries,
                  const std::vector<Evaluated>& res) const;
  void merge_mechanisms(const std::vector<Entry>& entries, std::vector<Evaluated>& res) const;
  double score(const Finding& f) const;
  /// Indices of the significant refits (or, with significant_only false, of every refit that
  /// lowers the error), best score first.
  std::vector<std::size_t> ranked(const std::vector<Evaluated>& res,
                                  bool significant_only = true) const;

  const Engine& engine_;
  const DiagnosisOptions& opt_;
  std::vector<std::unique_ptr<Hypothesis>> hyps_;
  std::vector<Entry> side_;                               // the declared model's screen, model-side
  std::vector<Entry> chosen_;                             // refitted on the declared model
  std::vector<Evaluated> res_;                            // their refits
  std::vector<std::unique_ptr<Joint>> joints_;            // the joint refits' hypotheses
  std::vector<std::size_t> first_;                        // significant refits, best first
  std::map<std::size_t, OwnParamsTest> own_params_tests_; // by index into res_
};

} // namespace thermnet::detail
