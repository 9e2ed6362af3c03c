#pragma once
/// Adding statements to case blocks of a model file (diagnose --write).

#include "lang/model.hpp"
#include "lang/rewrite/text_edit.hpp"

#include <map>
#include <string>
#include <vector>

namespace thermnet::rewrite {

/// The edits that insert each named case's lines (one per line, each indented and followed by
/// `comment`) just before the closing brace of its block (replacing the blanks before it) in file
/// `file`; a line `TARGET = ...` whose TARGET the block sets already (at its top) replaces that
/// setting in place instead (a case sets each key once), with a comment line saying so. The names
/// of the cases whose block is not in that file (or unknown) go to `elsewhere`.
std::vector<TextEdit> case_block_edits(const lang::Model& model, lang::FileId file,
                                       const std::map<std::string, std::string>& lines,
                                       const std::string& comment,
                                       std::vector<std::string>& elsewhere);

} // namespace thermnet::rewrite
