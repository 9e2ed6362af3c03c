#pragma once
/// The calibrated model as files (calibrate -o): the root file at OUT and, beside it, a copy of
/// every included file that declares a rewritten param or includes such a file, with the paths
/// written in the copies adjusted so that the new model reads the copies and the original data.

#include "lang/rewrite/param_values.hpp"
#include "lang/rewrite/text_edit.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace thermnet::rewrite {

/// A rewritten model that cannot go where it was asked to (onto one of its inputs, or to a path
/// a model file cannot name).
struct RewriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One file of a rewritten model.
struct RewrittenFile {
  std::string path;        ///< where it is to be written
  std::string text;        ///< its new text
  lang::FileId source = 0; ///< the model file it is a copy of
  bool chosen = false;     ///< its name was chosen here (a copy beside OUT), not given by the user
};

/// A file a model reads.
struct InputFile {
  std::string path; ///< as the model names it (relative paths joined to the naming file's folder)
  std::string role; ///< what it is: "the model", "the included file", "the data file", ...
};

/// Every file the model rooted at `root` reads: its own files (root first), then the files its
/// include, data, table and plugin statements name. `parsed` are syntax trees of its files already
/// at hand (a loaded model's): those files are not parsed again.
std::vector<InputFile> files_read(const lang::SourceManager& sources, lang::FileId root,
                                  const std::vector<const lang::ast::File*>& parsed = {});

/// The files of the model rooted at `root` with the params set to their new values, root first.
/// The root goes to `out`; every other file that changes goes beside `out` as `OUTSTEM.NAME`
/// (`OUTSTEM.STEM-2.EXT`, ... when that name is taken by an input or another copy, or is a symlink:
/// a name nobody gave is never written through). In each written file, includes of a copied file
/// name the copy, and relative include/data/table/plugin paths are re-expressed from the new
/// directory when it differs from the original's. Files that do not change are not copied; the
/// user's inputs are never targets. Throws RewriteError when `out` names an input of the model (the
/// model itself, an included, data, table or plugin file). `root_edits` are further edits of the
/// root file's original text (case blocks extended).
std::vector<RewrittenFile> rewrite_model(const lang::SourceManager& sources, lang::FileId root,
                                         const std::vector<ParamUpdate>& updates,
                                         const std::string& out,
                                         std::vector<TextEdit> root_edits = {});

} // namespace thermnet::rewrite
