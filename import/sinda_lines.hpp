#pragma once
/// Reading one line of each SINDA/FLUINT block into the deck (used by sinda_reader.cpp). Each
/// function throws ImportError for a line that is wrong, and says whether the line was used,
/// ignored (it changes no temperature) or not translated.

#include "import/sinda_deck.hpp"

#include <string>

namespace thermnet::importer::sinda {

/// What became of a line.
enum class LineUse {
  used,    ///< translated
  ignored, ///< changes no temperature (an output option, a solver setting): noted
  dropped  ///< not translated: listed, and the import fails unless a partial model is allowed
};

/// A line's use, and for ignored and dropped lines why (lines with the same reason are grouped).
struct LineResult {
  LineUse use = LineUse::used; ///< what became of it
  std::string why;             ///< the reason, for ignored and dropped lines
};

/// A NODE DATA line of submodel `sub`: `id, T, C` or `GEN id, n, inc, T, C`.
LineResult node_line(const SourceLine& line, const std::string& sub, Deck& deck);
/// A CONDUCTOR DATA line: `id, a, b, G` or `GEN id, n, inc, a, ainc, b, binc, G`.
LineResult conductor_line(const SourceLine& line, const std::string& sub, Deck& deck);
/// A SOURCE DATA line: `id, Q`.
LineResult source_line(const SourceLine& line, const std::string& sub, Deck& deck);
/// A CONTROL DATA line: `NAME = value, ...` (ABSZRO, SIGMA, TIMEND, TIMEO, OUTPUT, UID used).
LineResult control_line(const SourceLine& line, Deck& deck);
/// An OPTIONS DATA line (TITLE used, the rest changes no temperature).
LineResult options_line(const SourceLine& line, Deck& deck);
/// A VARIABLES 0 line: `SUB.Qn = SUB.Qn + value` is a heat load, anything else user logic.
LineResult variables0_line(const SourceLine& line, const std::string& sub, Deck& deck);
/// An OPERATIONS line: BUILD, the steady and transient solution calls and output calls are
/// understood, anything else is user logic.
LineResult operations_line(const SourceLine& line, Deck& deck);
/// An OUTPUT CALLS line: output routines change no temperature, anything else is user logic.
LineResult output_calls_line(const SourceLine& line);

} // namespace thermnet::importer::sinda
