#pragma once
/// Known events of a test campaign (a lid or a door opened): when each was on, per case, read from
/// the CSV file `thermnet diagnose --events` names. The `event_loss` hypothesis uses them.

#include "lang/signal.hpp"

#include <string>
#include <vector>

namespace thermnet {

/// One stretch of time during which a known event was on.
struct EventWindow {
  std::string case_name; ///< the case it belongs to (empty: every case)
  std::string event;     ///< the event's name ("event" when the file names none)
  double start = 0.0;    ///< s from the start of the case
  double end = 0.0;      ///< s, after start
};

/// Parses an events file: a header naming the columns `start` and `end` (s), optionally `case`
/// (empty or `*`: every case) and `event` (a name), in any order; one window a row. `cases` are
/// the model's case names (empty: not checked). Throws lang::CsvError naming the row and column
/// of a missing column, a bad number, an unknown case, end <= start, a negative start, or a
/// window overlapping another of the same event and case.
std::vector<EventWindow> parse_events(const std::string& text, const std::string& path,
                                      const std::vector<std::string>& cases);
/// Reads and parses an events file; throws lang::CsvError (row 0 when it cannot be read).
std::vector<EventWindow> read_events(const std::string& path,
                                     const std::vector<std::string>& cases);
/// The event names, in order of first appearance.
std::vector<std::string> event_names(const std::vector<EventWindow>& events);
/// When `event` is on in case `case_name` (its own windows and every-case ones; with an empty
/// `case_name`, only every-case ones): a step signal, 1 while on, 0 otherwise.
lang::Signal event_schedule(const std::vector<EventWindow>& events, const std::string& case_name,
                            const std::string& event);

} // namespace thermnet
