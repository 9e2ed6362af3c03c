#include "editors/lsp/document.hpp"

#include "app/model_loading.hpp"
#include "editors/lsp/uri.hpp"
#include "kernel/core/element_registry.hpp"
#include "lang/path_policy.hpp"

#include <exception>

#include <fmt/format.h>

namespace thermnet::lsp {

Document::Document(std::string uri, std::string text, long version)
    : uri_(std::move(uri)), path_(uri_to_path(uri_)), text_(std::move(text)), version_(version) {
  analyse();
}

void Document::update(std::string text, long version) {
  text_ = std::move(text);
  version_ = version;
  analyse();
}

void Document::analyse() {
  // The model points into the sources: drop it first, then rebuild all three together.
  model_.reset();
  diags_.reset();
  lines_ = std::make_unique<LineIndex>(text_);
  sources_ = std::make_unique<lang::SourceManager>();
  diags_ = std::make_unique<lang::DiagnosticEngine>(*sources_);
  // Files the document names are read from its folder tree only (an untitled document has none).
  lang::PathPolicy policy = lang::policy_for_model(path_);
  if (path_.empty()) policy.root = "/nonexistent/untitled document";
  lang::set_path_policy(policy);
  // A lower limit on what loops and submodels generate than the command line's: the editor gets
  // an answer within seconds (docs/language.md, Limits).
  lang::LoadOptions options = app::load_options(app::ModelPlugins::never, "the language server");
  options.max_generated = editor_max_generated;
  options.too_large_note =
      fmt::format("the language server stops at {} to answer within seconds; thermnet lint checks "
                  "up to {}",
                  editor_max_generated, lang::LoadOptions{}.max_generated);
  model_ = lang::Model::from_text(path_, text_, element_catalog(), *sources_, *diags_, options);
  try {
    model_->lint(*diags_);
  } catch (const std::exception& e) {
    lang::Diagnostic d;
    d.code = "internal-error";
    d.message = std::string("the linter stopped: ") + e.what();
    diags_->add(d);
  }
  diags_->sort();
  long id = sources_->find(path_);
  root_ = id < 0 ? 0 : static_cast<lang::FileId>(id);
}

} // namespace thermnet::lsp
