#pragma once
/// The Python module's C++ side without Python: a loaded, linted model with the sources it was read
/// from, and the commands' operations on it returning the same values and JSON as the CLI.

#include "kernel/core/simulation.hpp"
#include "lang/model.hpp"
#include "lang/path_policy.hpp"
#include "lang/source.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace thermnet::python {

/// A model that could not be loaded: the first error's place and every diagnostic as text.
struct LoadError : std::runtime_error {
  /// The message (compiler-style, all diagnostics) and the first error's place.
  LoadError(const std::string& message, std::string file, std::uint32_t line, std::uint32_t column)
      : std::runtime_error(message), file(std::move(file)), line(line), column(column) {}
  std::string file;         ///< file of the first error (empty when none applies)
  std::uint32_t line = 0;   ///< its 1-based line (0 when none applies)
  std::uint32_t column = 0; ///< its 1-based column (0 when none applies)
};

/// Builds a LoadError from a model error raised while running (e.g. an unknown case).
LoadError load_error_of(const lang::ModelError& e, const lang::SourceManager& sources);

/// What simulate() runs: a case, param overrides and the CLI's simulate options.
struct SimulateRequest {
  std::string case_name;          ///< case (empty: the only one or the default)
  lang::ParamValues params;       ///< param overrides, SI
  std::vector<std::string> nodes; ///< nodes to keep (empty: all)
  std::optional<double> duration; ///< duration override, s
  std::optional<double> output;   ///< output interval override, s
  bool steady = false;            ///< steady state at t = 0
  bool sensors = false;           ///< add each sensor's reading after the nodes (`--sensors`)
  double rtol = 1e-6;             ///< relative tolerance
  double atol = 1e-6;             ///< absolute tolerance, K
};

/// What calibrate() runs: the `thermnet calibrate` options.
struct CalibrateRequest {
  std::string method = "lm";      ///< optimizer name
  std::size_t samples = 0;        ///< budget (0: the method's default)
  double tolerance = 5.0;         ///< acceptance limit, K
  std::uint64_t seed = 1;         ///< random seed
  int threads = 0;                ///< worker threads (0: all cores)
  std::vector<std::string> cases; ///< cases to compare (empty: all with data)
};

/// A linted model and the sources it was read from; const operations are thread-safe.
class ModelSession {
public:
  /// Loads and lints a model file; throws LoadError on any error diagnostic (warnings pass).
  static std::shared_ptr<const ModelSession> load(const std::string& path);
  /// Loads and lints a model from text, as if read from `path` (includes and data relative to it).
  static std::shared_ptr<const ModelSession> from_text(const std::string& text,
                                                       const std::string& path);

  /// The model.
  const lang::Model& model() const { return *model_; }
  /// Node and boundary names, declaration order.
  std::vector<std::string> node_names() const;
  /// Case names, declaration order (empty when the model has none).
  std::vector<std::string> case_names() const;

  /// Simulates a case; the result keeps only the requested nodes (all when none; with `sensors`,
  /// the sensors' readings follow the nodes as columns named after the sensors and may be
  /// requested like nodes). Throws LoadError for model errors, std::invalid_argument for unknown
  /// params or nodes, SolverError.
  SimulationResult simulate(const SimulateRequest& request) const;
  /// `thermnet calibrate --json` report of a calibration run.
  nlohmann::ordered_json calibrate(const CalibrateRequest& request) const;
  /// `thermnet diagnose --json` report.
  nlohmann::json diagnose(const std::vector<std::string>& cases, int threads,
                          std::size_t top) const;
  /// `thermnet sensitivity --json` report.
  nlohmann::json sensitivity(const std::vector<std::string>& cases, bool elements,
                             int threads) const;

private:
  static std::shared_ptr<const ModelSession> checked(std::unique_ptr<lang::SourceManager> sources,
                                                     std::unique_ptr<lang::Model> model,
                                                     lang::DiagnosticEngine& diags,
                                                     const std::string& path);
  std::unique_ptr<lang::SourceManager> sources_;
  std::unique_ptr<lang::Model> model_;
  lang::PathPolicy policy_; ///< where the files the model names may lie (set for each run)
};

} // namespace thermnet::python
