// The diagnosis's entry point: the evidence/fit engine measures the baseline, and unless it is at
// the noise floor the selection screens, refits and selects the findings (engine.hpp,
// selection.hpp; the hypotheses live in plugins/diagnosis/).

#include "kernel/diagnosis/diagnosis.hpp"

#include "kernel/diagnosis/prediction_selection.hpp"
#include "kernel/diagnosis/selection.hpp"

#include <chrono>
#include <ctime>
#include <optional>

namespace thermnet {

DiagnosisReport diagnose(const lang::Model& model, const DiagnosisOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  if (options.progress)
    options.progress({"reading the data, simulating the baseline and the heat flows", 0, 0});
  const detail::Engine engine(model, options);
  DiagnosisReport rep;
  rep.setup_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rep.model = model.path();
  for (const auto& ce : engine.evidence().cases)
    rep.cases.push_back(ce.name);
  rep.noise_floor = engine.evidence().noise_floor;
  rep.validation = engine.validation();
  rep.split_cases = engine.split_cases();
  rep.case_folds = engine.case_folds();
  rep.folds = engine.folds();
  rep.baseline = engine.declared().metrics;
  rep.at_noise_floor = engine.declared().at_floor;
  rep.criterion = options.criterion;
  rep.min_gain = options.min_gain;
  // Under the prediction criterion the likelihood-ratio tests decide (a model at the noise floor
  // gains nothing significant there either); the output error's selection otherwise, which also
  // describes the error its last model leaves.
  // (the declared model's base is referred to, not copied: it holds every measured point's
  // simulation and residuals, hundreds of MB for a data file of 10^6 rows)
  const detail::Base* last = &engine.declared();
  detail::Base selected_last;
  std::optional<detail::Base> selected;
  const auto tell = [&](const char* stage) {
    if (options.progress) options.progress({stage, 0, 0});
  };
  if (options.criterion == "prediction") {
    tell("fitting the candidates by the likelihood of their one-step-ahead predictions");
    selected = detail::select_by_likelihood(engine, options, rep);
  } else if (!rep.at_noise_floor) {
    tell("screening the candidates on the unexplained heat flows");
    selected = detail::Selection(engine, options).run(rep, selected_last);
    last = &selected_last;
  }
  const detail::Base& best = selected ? *selected : engine.declared();
  if (options.criterion != "prediction") {
    rep.structural = detail::residual_signature(engine.evidence(), last->sims, last->metrics.rmse);
    // An error left far above the noise, and somewhere as large as the gain a finding must make
    // (--min-gain): below that no finding is accepted, so none is missing (a model's own
    // simulation fed back, its solver's millikelvins against a noise floor of their jitter).
    rep.structural.remains = !last->at_floor && last->metrics.rmse >= 2.0 * rep.noise_floor &&
                             last->metrics.worst_window_rmse() >= options.min_gain;
  }
  // (a selection draws its findings' curves itself: `after` is the best finding's model, as
  // --plot draws it, and the steps every finding's)
  if (rep.curves.empty()) rep.curves = engine.curves(best, best);
  // (the likelihood steps' batches, added by the selection, come after the engine's)
  rep.batches.insert(rep.batches.begin(), engine.batches().begin(), engine.batches().end());
  rep.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rep.cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  return rep;
}

} // namespace thermnet
