#include "cli/run_command.hpp"

#include "app/model_loading.hpp"
#include "app/output_stream.hpp"
#include "kernel/core/network.hpp"
#include "kernel/core/solver_types.hpp"
#include "kernel/diagnosis/diagnosis.hpp"
#include "kernel/estimation/estimator.hpp"
#include "lang/csv.hpp"
#include "lang/display_text.hpp"
#include "lang/model.hpp"
#include "lang/rewrite/model_files.hpp"

#include <fmt/format.h>

#include <iostream>
#include <stdexcept>

namespace thermnet::cli {
using namespace app;
namespace {

int report(const std::string& who, const std::exception& e, int status) {
  std::cerr << fmt::format("{}: error: {}\n", who, lang::escape_for_display(e.what()));
  return status;
}

} // namespace

int run_command(const std::string& who, const CommandBody& body, int invalid_argument_status) {
  lang::SourceManager sources;
  try {
    const int status = body(sources);
    try {
      flush_standard_output();
    } catch (const OutputError& e) {
      return report(who, e, status != exit_ok ? status : exit_usage);
    }
    return status;
  } catch (const lang::ModelError& e) {
    return report_model_error(e, sources);
  } catch (const lang::CsvError& e) {
    return report(who, e, e.row == 0 ? exit_usage : exit_failure); // row 0: the file is unreadable
  } catch (const OutputError& e) {
    return report(who, e, exit_usage);
  } catch (const rewrite::RewriteError& e) {
    return report(who, e, exit_usage);
  } catch (const SolverError& e) {
    return report(who, e, exit_failure);
  } catch (const NetworkError& e) {
    return report(who, e, exit_failure);
  } catch (const EstimatorError& e) {
    return report(who, e, exit_failure);
  } catch (const DiagnosisError& e) {
    return report(who, e, exit_failure);
  } catch (const lang::OverrideError& e) {
    if (!e.diag) return report(who, e, exit_usage);
    print_diagnostic(*e.diag, sources);
    return exit_usage;
  } catch (const std::invalid_argument& e) {
    return report(who, e, invalid_argument_status);
  }
}

} // namespace thermnet::cli
