#pragma once
/// What surrounds the cursor in a model's text: the word under it and the statement before it.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::lsp {

/// An identifier in the text.
struct Word {
  std::size_t begin = 0; ///< first byte
  std::size_t end = 0;   ///< one past the last byte
  std::string text;      ///< the identifier
};

/// The identifier (letters, digits, '_') containing or ending at byte offset `at`, if any.
std::optional<Word> word_at(std::string_view text, std::size_t at);

/// True when the word is followed by `=` (not `==`): it names a key.
bool followed_by_assignment(std::string_view text, const Word& w);

/// The statement the cursor is in, from the text before the cursor.
struct StatementContext {
  std::vector<std::string> tokens; ///< complete tokens before the cursor ("=" is its own token)
  std::string partial;             ///< identifier being typed at the cursor (may be empty)
  std::string object;              ///< for `film.P`: "film" (partial is then the member)
  bool inner = false;              ///< the statement starts after `{` or `;` (a block item)
  std::string block;               ///< first word of the enclosing `{` block ("case", "series",..)
  bool in_comment = false;         ///< the cursor is inside a `#` comment
  bool in_string = false;          ///< the cursor is inside a string

  /// True when the cursor is where a value goes (after `=`, an operator or an open bracket).
  bool value_position() const;
  /// The key whose value is being written (the identifier before the last `=`), or "".
  std::string current_key() const;
  /// Positional words of the statement: tokens before the first `key =`.
  std::size_t positional_count() const;
  /// Keys already given in the statement.
  std::vector<std::string> given_keys() const;
};

/// The context of byte offset `at`.
StatementContext context_at(std::string_view text, std::size_t at);

/// An identifier of the model's code (not of a comment or string) with its statement's context.
struct CodeWord {
  Word word;              ///< the identifier
  StatementContext where; ///< the statement it is in, up to the identifier's start
};

/// The identifier at byte offset `at` and its context, unless there is none or it is in a comment
/// or string.
std::optional<CodeWord> code_word_at(std::string_view text, std::size_t at);

/// The full name the identifier `w` is part of, blanks removed: the instance path and indices
/// before it and its own indices (`u1.pcb` for `pcb` in `u1.pcb.T0`, `p[3,7]` for `p[3, 7]`).
std::string qualified_name(std::string_view text, const Word& w);

/// The byte offset where `for ... NAME in` declares the loop variable `w` names (the nearest
/// such loop header at or before it), or nothing.
std::optional<std::size_t> loop_variable(std::string_view text, const Word& w);

} // namespace thermnet::lsp
