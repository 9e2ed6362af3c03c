#pragma once
/// `thermnet import`'s work without the command line: reads SINDA/FLUINT decks or SPICE netlists
/// (the format told, or found from the content), and writes the model as thermnet text.

#include "lang/diagnostics.hpp"

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::importer {

/// The formats thermnet imports.
enum class Format { automatic, sinda, spice };

/// How to import.
struct ImportOptions {
  Format format = Format::automatic; ///< the files' format (automatic: from their content)
  bool allow_partial = false;        ///< write the model even when lines were not translated
  /// Whether a name is an element kind (a submodel may not take it); empty: the core kinds.
  std::function<bool(const std::string&)> is_kind;
};

/// What an import produced.
struct ImportResult {
  std::string text;                    ///< the model's text ("" when the import failed)
  std::vector<std::string> files_read; ///< every file read (the named ones and their includes)
  Format format = Format::automatic;   ///< the format read
  bool failed = false;                 ///< errors, or lines not translated without allow_partial
  bool unreadable = false;             ///< a file could not be read (exit status 2)
  std::size_t dropped = 0;             ///< lines (or groups of lines) not translated
  std::size_t nodes = 0;               ///< nodes written
  std::size_t boundaries = 0;          ///< boundaries written
  std::size_t links = 0;               ///< links written
  std::size_t heaters = 0;             ///< heaters written
};

/// The format a file's text looks like: SINDA when a line starts with HEADER, SPICE when lines
/// are element cards or dot directives; automatic when it cannot tell.
Format detect_format(std::string_view text);

/// The format's name as the command line spells it.
const char* format_name(Format f);

/// Imports `paths` (merged into one model); every problem, untranslated line and note goes to
/// `diags` (whose sources receive every file read).
ImportResult import_files(const std::vector<std::string>& paths, const ImportOptions& options,
                          lang::DiagnosticEngine& diags, lang::SourceManager& sources);

} // namespace thermnet::importer
