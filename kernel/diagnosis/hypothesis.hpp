#pragma once
/// Diagnosis hypothesis plugins: each finding kind proposes candidate model extensions from the
/// evidence (the fast screen), says how its extra parameters change a simulation, and writes the
/// netlist statements that add it (in the manner of kernel/calibration/optimizer.hpp).

#include "kernel/core/measured_data.hpp"
#include "kernel/core/registry.hpp"
#include "kernel/core/row_matrix.hpp"
#include "kernel/diagnosis/events.hpp"
#include "lang/model.hpp"
#include "lang/network_spec.hpp"

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace thermnet {

/// What one case tells the screen: the measured and baseline-simulated temperatures and each
/// measured node's unexplained heat flow q = C dT/dt - (sum of flows + sources), in W.
struct CaseEvidence {
  std::string name;                           ///< case name
  lang::NetworkSpec spec;                     ///< the case at the declared param values
  MeasuredData measured;                      ///< its data (K)
  std::vector<std::vector<double>> simulated; ///< baseline, per measured series, at the times
  RowMatrix T;                                ///< T[k][node]: smoothed measured, else simulated
  RowMatrix dTdt;                             ///< dTdt[k][node]: smoothed slope, K/s
  RowMatrix q;                                ///< q[k][node]: unexplained heat flow, W
  std::vector<int> rows;                      ///< spec nodes with q (measured unknown nodes)
  /// Times (measured times) of the case, s.
  const std::vector<double>& times() const { return measured.times; }
};

/// A least-squares fit of the unexplained heat flows to one candidate term.
struct ScreenFit {
  double coefficient = 0.0; ///< fitted coefficient of the term
  double reduction = 0.0;   ///< drop of the weighted sum of squares ((K/s)^2 summed)
  double correlation = 0.0; ///< correlation of the term with the unexplained flows
};

/// A network as written in the model at the declared param values: what a finding's netlist text
/// is written against.
struct DeclaredSpec {
  std::string case_name;  ///< the case block (empty: the declarations without any case)
  lang::NetworkSpec spec; ///< the elaborated network
};

/// Everything the hypotheses see: per-case evidence and the noise floor.
struct Evidence {
  const lang::Model* model = nullptr; ///< the model under diagnosis
  std::vector<CaseEvidence> cases;    ///< cases with data
  double noise_floor = 0.0;           ///< estimated measurement noise, K
  double screen_total = 0.0; ///< weighted sum of squares of q over every row (sum_screen())
  DeclaredSpec declared;     ///< the declarations without any case
  std::vector<DeclaredSpec> declared_cases; ///< every declared case block, with data or not
  std::vector<EventWindow> events;          ///< known events (`--events`), for event_loss
  int threads = 1; ///< worker threads a hypothesis may screen its candidates on (0: all cores)

  /// Sets screen_total from q (once the cases' q are filled; regress() reads it).
  void sum_screen();
  /// Fits q ~ c * basis(case, node, k) over every screen row (rows weighted by 1/C, i.e. in K/s);
  /// basis returning 0 contributes nothing; with a `support`, basis is asked only at those nodes
  /// (taken as 0 at the others). Needs screen_total (sum_screen()).
  ScreenFit regress(const std::function<double(std::size_t c, int node, std::size_t k)>& basis,
                    const std::vector<int>& support = {}) const;
  /// Spec index of a node by name in the first case (-1 if absent).
  int node_index(const std::string& name) const;
  /// True when a spec node is measured (has q) in some case.
  bool measured(int node) const;
  /// True when a spec node is neither measured nor a boundary (a candidate there is unobserved).
  bool unobserved(int node) const;
};

/// A proposed extension: kind, where, its extra parameters and the screen's score.
struct Candidate {
  std::string kind;               ///< finding kind (the plugin's name)
  std::vector<std::string> nodes; ///< nodes it concerns
  std::string element;            ///< element it concerns (heater_gain)
  std::string mechanism;          ///< one of the kind's mechanisms (missing_link: "linear"...)
  std::vector<std::string> names; ///< names of the extra parameters (e.g. "G")
  std::vector<double> start;      ///< starting values
  std::vector<double> lo;         ///< lower bounds
  std::vector<double> hi;         ///< upper bounds
  bool measurement_side = false;  ///< acts on the simulated series, not the model
  /// On unmeasured nodes only, so the screen cannot score it (screen 0): refitted when a
  /// shortlisted candidate of its kind names a neighbour in its place, or when its kind has few
  /// such candidates (one per heater).
  bool unobserved = false;
  double screen = 0.0;              ///< screen score (larger is better; model-side comparable)
  std::string evidence;             ///< what the screen saw, in words
  std::vector<int> index;           ///< resolved spec indices (nodes, element) for the plugin
  std::vector<EventWindow> windows; ///< when it acts, by case (event_loss: its event's windows)
  /// Where a node the candidate adds starts, by case name, K (start_temperatures()).
  std::map<std::string, double> start_T;
};

/// Netlist lines for inside case blocks, by case name.
using CaseLines = std::map<std::string, std::string>;

/// Appends `more` to `lines` (a line break between the lines of a case).
void merge_case_lines(CaseLines& lines, const CaseLines& more);

/// One finding kind: proposes candidates, applies them and says how they are written. Everything
/// the engine, the report and `--write` do differently for a kind is asked of its hypothesis (or
/// read from the candidates it proposes: `measurement_side`, `mechanism`, `element`).
class Hypothesis {
public:
  virtual ~Hypothesis() = default;
  /// Candidates from the evidence (scored by the screen where the kind allows); runs beside the
  /// other kinds' propose, on its own thread.
  virtual std::vector<Candidate> propose(const Evidence& ev) const = 0;
  /// The candidates the likelihood criterion tests: propose()'s, plus those its output-error
  /// screen turned away where the kind can be tested without it (default: propose()'s).
  virtual std::vector<Candidate> propose_for_likelihood(const Evidence& ev) const {
    return propose(ev);
  }
  /// The alternative mechanisms its candidates name (e.g. linear, radiation), in the order the
  /// report lists them; candidates of one site with different mechanisms are compared, and one is
  /// kept (default: none).
  virtual std::vector<std::string> mechanisms() const { return {}; }
  /// True when it recalibrates the model's ranged params: always refitted (not shortlisted by
  /// the screen), the basis of the joint refit, and not proposed again once a finding has
  /// recalibrated them (default: false).
  virtual bool recalibrates() const { return false; }
  /// True when a fit at p is another kind's candidate in disguise (input_split: all of a power
  /// through a mass is a heater's own mass): it is not reported, the other kind is (default:
  /// false).
  virtual bool degenerate(const Candidate&, const std::vector<double>& /*p*/) const {
    return false;
  }
  /// True when its candidates move their element's effect elsewhere (a heater's power onto a
  /// mass, a link split around one): once such a finding is applied, no other one of this sort
  /// names the same element (default: false).
  virtual bool reroutes() const { return false; }
  /// Other starting points of a candidate's parameters, tried beside c.start where its fit has
  /// local minima (a mass's time constant and place: a refit from one start can stay where it
  /// began); each as long as c.start (default: none).
  virtual std::vector<std::vector<double>> restarts(const Candidate&) const { return {}; }
  /// Param overrides for Model::instantiate at parameters p (default: none).
  virtual lang::ParamValues overrides(const Candidate&, const std::vector<double>&) const {
    return {};
  }
  /// Extends an instantiated case at parameters p (default: nothing).
  virtual void extend(const Candidate&, const std::vector<double>&, lang::NetworkSpec&) const {}
  /// True when correct() may change the series of candidate c (default: c.measurement_side; the
  /// sensitivities' Jacobians differentiate the corrections of such candidates only).
  virtual bool corrects(const Candidate& c) const { return c.measurement_side; }
  /// Corrects the simulated series of a spec node at parameters p (measurement-side kinds).
  virtual void correct(const Candidate&, const std::vector<double>&, int /*node*/,
                       const std::vector<double>& /*times*/, std::vector<double>& /*sim*/) const {}
  /// Netlist statements that add the finding to the model's top level (one per line).
  virtual std::string statement(const Candidate& c, const std::vector<double>& p,
                                const Evidence& ev) const = 0;
  /// Lines that complete the finding inside case blocks, by case name (one per line), where the
  /// top-level statements alone would not reproduce the fit (default: none).
  virtual CaseLines case_statements(const Candidate&, const std::vector<double>&,
                                    const Evidence&) const {
    return {};
  }
  /// Params whose declared values `--write` rewrites to apply the finding (name -> SI value),
  /// in place of appending its statements (default: none).
  virtual lang::ParamValues rewrites(const Candidate&, const std::vector<double>&) const {
    return {};
  }
  /// Elements of the model whose declarations `--write` comments out because the statements
  /// replace them (wall_mass: the link it splits; default: none).
  virtual std::vector<std::string> retires(const Candidate&, const Evidence&) const { return {}; }
};

/// A named hypothesis kind with a one-line doc and a factory.
struct HypothesisPlugin {
  static constexpr const char* family = "hypothesis";  ///< registry family name
  std::string name;                                    ///< finding kind, e.g. "missing_link"
  std::string doc;                                     ///< one line for docs and --help
  std::function<std::unique_ptr<Hypothesis>()> create; ///< factory
  std::string screen; ///< the term the screen fits to the unexplained heat flows (docs)
  std::string fitted; ///< the fitted size of the effect and its unit (docs)
  std::string writes; ///< what --write adds to the model for it (docs)
};

/// All hypothesis kinds.
using HypothesisRegistry = Registry<HypothesisPlugin>;

/// A number as netlist text (enough digits to round-trip a fitted value usefully).
std::string netlist_number(double v);

/// A constant or step/pwl signal as netlist text, each value followed by ` [unit]` unless `unit`
/// is empty (corner times in s).
std::string signal_text(const lang::Signal& s, const std::string& unit);

/// True when two signals have the same shape and values.
bool same_signal(const lang::Signal& a, const lang::Signal& b);

/// Indices of the spec's heaters that have a name and a power P and heat a node, not a boundary
/// (the ones a finding can name).
std::vector<int> named_heaters(const lang::NetworkSpec& spec);

/// The power P of the heater named `element` in a declared network; throws std::logic_error when
/// it has none.
const lang::Signal& heater_power(const DeclaredSpec& d, const std::string& element);

/// A plugin element of `kind` between `nodes` (spec indices) with constant key values (SI);
/// throws std::invalid_argument when no plugin provides the kind.
lang::ElementSpec make_element(const std::string& kind, const std::string& name,
                               std::vector<int> nodes, const std::map<std::string, double>& keys);

/// `base`, or `base_2`, `base_3`... whichever names no element or node of the spec.
std::string unique_name(const lang::NetworkSpec& spec, const std::string& base);

/// `base`, or `base_2`, `base_3`... whichever names no element, node or param of the model
/// (the names a finding's statements declare).
std::string unique_model_name(const Evidence& ev, const std::string& base);

/// The median interval between samples over every case, s (0 with fewer than two samples).
double sampling_interval(const Evidence& ev);

/// The longest time span of a case, s.
double longest_span(const Evidence& ev);

/// Restarts of a mass's (C, tau) parameters k and k + 1 (restarts()): tau four times longer and
/// shorter, and C four times larger and smaller, each within the candidate's box.
std::vector<std::vector<double>> mass_restarts(const Candidate& c, std::size_t k);

/// The time constants a hidden mass's screen tries: from three sampling intervals to half the
/// longest case, a factor of two apart.
std::vector<double> screen_taus(const Evidence& ev);

/// A sampled series through a first-order lag tau (dy/dt = (u - y) / tau, u linear between the
/// samples), starting at y0.
std::vector<double> lowpass(const std::vector<double>& times, const std::vector<double>& u,
                            double tau, double y0);

/// The temperature of `node` at the first sample of each case as the data say (case name -> K):
/// the smoothed measurement, the simulated start where it is not measured.
std::map<std::string, double> start_temperatures(const Evidence& ev, int node);

/// The steady state at t = 0 of spec node `node` with its neighbours at their starts: the sum
/// over its linear links of constant conductance of G times the other end's start, plus the power
/// of its heaters at t = 0, over the sum of the G's, K (nullopt without such a link). A neighbour
/// starts at `known` where it names it (spec index -> K), else at its T0, a boundary at its
/// temperature at t = 0, else at the case's initial.
std::optional<double> steady_start(const lang::NetworkSpec& spec, int node,
                                   const std::map<int, double>& known);

/// The name of the parameter that places an added node's start between the steady state around
/// it (0) and the temperature of the node it hangs off at the first sample (1).
inline constexpr const char* kStartShare = "start_share";

/// The candidate with a free start for the node it adds: the parameter kStartShare appended,
/// within [0, 1], from 0 (the steady state). One share for every case: a start fitted per case
/// would be fitted on a left-out case's own data when cases are held out in turn.
Candidate with_start_share(const Candidate& c);

/// Whether a candidate may name nodes an applied finding added (not in the declared model).
enum class AddedNodes { refused, allowed };

/// True when the candidate is a site of the model's own: its element (if any) is declared in
/// `declared`, and, where `nodes` is refused, so is every node it names. An element a finding
/// added (a split's heater) never is; a node it added (the envelope) may be, by policy.
bool on_model_sites(const Candidate& c, const lang::NetworkSpec& declared, AddedNodes nodes);

/// The share of a fit p where the candidate carries one (with_start_share); nullopt otherwise.
std::optional<double> start_share(const Candidate& c, const std::vector<double>& p);

/// The restart at the other end of the start share (the node's own temperature), or nothing.
std::vector<std::vector<double>> start_restarts(const Candidate& c);

/// Sets where node `mass`, which a candidate's extension has just added to `spec` with its links
/// and heaters, starts in the spec's case: at the steady state around it at t = 0 (steady_start,
/// with `anchor` at the data's start of the case from start_T), moved by the candidate's fitted
/// start share towards the anchor's start. A test rarely starts in a steady state: the local
/// steady state puts a wall between a warm room and the cold outdoors where the two ends hold it,
/// a wall that shared the room's heated history starts nearer the room; the share lets the data
/// say which.
void place_start(const Candidate& c, const std::vector<double>& p, lang::NetworkSpec& spec,
                 int mass, int anchor);

/// Where the node that `h` adds last starts in each case of the evidence at p (case name -> K):
/// h.extend on each case's network. Empty where the extension cannot be made on them.
std::map<std::string, double> added_starts(const Hypothesis& h, const Candidate& c,
                                           const std::vector<double>& p, const Evidence& ev);

/// ` T0 = X` (degC) for the declaration of a node a finding adds: its start in the first case
/// (by name) of `starts`; empty when unknown.
std::string start_text(const std::map<std::string, double>& starts);

/// `NODE.T0 = X` for every declared case block with data whose start differs from start_text's.
CaseLines start_case_lines(const std::map<std::string, double>& starts, const std::string& node,
                           const Evidence& ev);

/// How the node a finding adds starts at the fit p, in words (the steady state around it, the
/// temperature of its node, or the fitted share between the two).
std::string start_words(const Candidate& c, const std::vector<double>& p);

/// True when parameter j of a candidate's fit p ended on its lower (or upper) bound: within 1e-3
/// of its box (of the logarithm's for a positive range), where a least-squares fit pressed
/// against the box stops.
bool on_bound(const Candidate& c, const std::vector<double>& p, std::size_t j, bool upper);

/// Adds a node of capacity C [J/K] starting at T0 (K; none: the case's initial) to a spec, named
/// `base` or a free variant of it, and returns its index.
int add_node(lang::NetworkSpec& spec, const std::string& base, double C, std::optional<double> T0,
             const std::string& doc);

/// Adds a mass (add_node) tied to spec node `node` by a conductance G [W/K] named `base`_g, and
/// returns the mass's index.
int add_tied_mass(lang::NetworkSpec& spec, const std::string& base, double C,
                  std::optional<double> T0, const std::string& doc, int node, double G);

/// The statements declaring a mass a finding adds, tied to `node`: ranged params MASS_C and
/// MASS_G (their ranges from the candidate's box for C and tau = C / G, its parameters k and
/// k + 1, p their values), the node MASS (`start`: its start_text, `doc`) and the conductance
/// MASS_g. MASS is `base` or a free variant of it in the model.
std::string tied_mass_statements(const Evidence& ev, const Candidate& c, std::size_t k,
                                 const std::vector<double>& p, const std::string& base,
                                 const std::string& node, const std::string& doc,
                                 const std::string& start);

/// Why the screen has no unexplained heat flow for a node of a candidate, in words: it is not
/// measured, or its sensor was found faulty by an applied finding (screened with its simulated
/// temperature).
std::string unscreened_words(const Evidence& ev, int node);

/// True when a spec node has a measured series in some case (whether or not it is screened).
bool sensed(const Evidence& ev, int node);

/// A ranged param declaration for a finding's statements:
/// `param NAME = VALUE [UNIT] range LO [UNIT] .. HI [UNIT] "DOC"` (values SI).
std::string param_statement(const std::string& name, double value, double lo, double hi,
                            const std::string& unit, const std::string& doc);

} // namespace thermnet
