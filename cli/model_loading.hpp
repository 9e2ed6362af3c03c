#pragma once
/// Loading models for the subcommands: one place that wires the registry and plugin loading.

#include "lang/diagnostics.hpp"
#include "lang/model.hpp"

#include <memory>
#include <string>

namespace thermnet::cli {

/// Loads a model against the global element registry; problems go to diags.
std::unique_ptr<lang::Model> load_model(const std::string& path, lang::SourceManager& sources,
                                        lang::DiagnosticEngine& diags);

/// True when stderr/stdout should be coloured (a terminal, and NO_COLOR unset).
bool use_color(int fd);

} // namespace thermnet::cli
