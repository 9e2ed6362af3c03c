#pragma once
/// A model loaded from a file for tests, with the sources and diagnostics it needs kept alive.

#include "kernel/core/element_registry.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"
#include "lang/source.hpp"

#include <doctest/doctest.h>

#include <memory>
#include <string>

namespace thermnet::test {

/// Whether loading also requires the model to lint without errors.
enum class Lint { skip, clean };

/// A model loaded from `path` (the test fails when it cannot be loaded, or linted clean).
struct LoadedModel {
  lang::SourceManager sources;           ///< the files read
  lang::DiagnosticEngine diags{sources}; ///< the problems found
  std::unique_ptr<lang::Model> model;    ///< the model

  /// Loads the model; with Lint::clean also lints it and requires no error.
  explicit LoadedModel(const std::string& path, Lint lint = Lint::skip) {
    model = lang::Model::load(path, thermnet::element_catalog(), sources, diags);
    REQUIRE(model);
    if (lint == Lint::skip) return;
    model->lint(diags);
    INFO(lang::render_text(diags));
    REQUIRE(diags.error_count() == 0);
  }
};

} // namespace thermnet::test
