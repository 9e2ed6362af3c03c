#pragma once
/// An open document of the language server and its latest analysis (parse, declarations, lint).

#include "editors/lsp/position.hpp"
#include "lang/diagnostics.hpp"
#include "lang/model.hpp"

#include <memory>
#include <string>

namespace thermnet::lsp {

/// Most declarations and iterations the loops and submodels of an open document may generate
/// (the command line allows lang::LoadOptions' default).
inline constexpr std::size_t editor_max_generated = 500'000;

/// The text of an open model and what the linter made of it; re-analysed on every change.
class Document {
public:
  /// Opens a document and analyses it.
  Document(std::string uri, std::string text, long version);
  /// Replaces the whole text (full synchronisation) and analyses it again.
  void update(std::string text, long version);

  /// The document's URI as the client names it.
  const std::string& uri() const { return uri_; }
  /// The file path the model is read under (includes and data files resolve against it).
  const std::string& path() const { return path_; }
  /// The current text.
  const std::string& text() const { return text_; }
  /// The client's version of the text.
  long version() const { return version_; }
  /// The model (never null after analysis).
  const lang::Model& model() const { return *model_; }
  /// The sources of the analysis (the document and its includes).
  const lang::SourceManager& sources() const { return *sources_; }
  /// The id of the document itself among the sources.
  lang::FileId root() const { return root_; }
  /// The line starts of the current text (positions in time proportional to lines, not text).
  const LineIndex& lines() const { return *lines_; }
  /// Every diagnostic of the analysis, sorted.
  const lang::DiagnosticEngine& diagnostics() const { return *diags_; }

private:
  void analyse();
  std::string uri_;
  std::string path_;
  std::string text_;
  long version_ = 0;
  std::unique_ptr<lang::SourceManager> sources_;
  std::unique_ptr<lang::DiagnosticEngine> diags_;
  std::unique_ptr<lang::Model> model_;
  lang::FileId root_ = 0;
  std::unique_ptr<LineIndex> lines_;
};

} // namespace thermnet::lsp
