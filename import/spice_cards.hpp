#pragma once
/// The lexical layer of SPICE netlists: the title line, `*` comment lines, `;` trailing comments,
/// `+` continuation lines and `.include`, giving cards (logical lines) of tokens with their
/// places; `{expr}` and `'expr'` are one token each.

#include "import/input_files.hpp"
#include "import/report.hpp"

#include <string>
#include <vector>

namespace thermnet::importer::spice {

/// One token of a card.
struct Token {
  /// What the token is.
  enum class Kind {
    word,       ///< a name, a number or a keyword
    expression, ///< `{...}` or `'...'` (text without the delimiters)
    open,       ///< (
    close,      ///< )
    equals      ///< =
  };
  Kind kind = Kind::word;        ///< its kind
  std::string text;              ///< its text (an expression: without its delimiters)
  lang::Span at;                 ///< where it stands
  std::uint32_t text_offset = 0; ///< byte offset of `text` in its file (for expressions' errors)
};

/// A card: a line of the netlist with its continuation lines.
struct Card {
  std::vector<Token> tokens; ///< its tokens (never empty)
  lang::Span at;             ///< its first line
};

/// The cards of the netlist (the first file: its first line is the title), and of the other files
/// and the files `.include` names (no title line), in order; `.end` ends a file.
struct Netlist {
  std::string title;              ///< the title line
  lang::Span title_at;            ///< where
  std::vector<Card> cards;        ///< every card, includes expanded
  std::vector<std::string> files; ///< every file read, as named
};

/// Reads the netlist files; problems go to `report`.
Netlist read_cards(const std::vector<std::string>& paths, lang::SourceManager& sources,
                   Report& report);

/// `text` in lower case (ASCII).
std::string lower(std::string_view text);

} // namespace thermnet::importer::spice
