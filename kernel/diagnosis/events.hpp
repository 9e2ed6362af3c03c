#pragma once
/// Known events of a test campaign (a lid or a door opened): when each was on, per case, read from
/// the CSV file `thermnet diagnose --events` names. The `event_loss` hypothesis uses them.

#include "lang/signal.hpp"

#include <optional>
#include <string>
#include <vector>

namespace thermnet {

/// One stretch of time during which a known event was on.
struct EventWindow {
  std::string case_name; ///< the case it belongs to (empty: every case)
  std::string event;     ///< the event's name ("event" when the file names none)
  double start = 0.0;    ///< s from the start of the case
  double end = 0.0;      ///< s, after start
  /// From an event log: start and end are UNIX times (s) that place_events() puts in each case
  bool absolute = false;
};

/// When a case happens: what place_events() needs to put a log's events in it.
struct CaseClock {
  std::string name;            ///< the case
  double duration = 0.0;       ///< s
  std::optional<double> epoch; ///< UNIX time of its start, s (a data file with UNIX/ISO times)
};

/// Parses an events file, in one of two forms. Windows: a header naming the columns `start` and
/// `end` (s), optionally `case` (empty or `*`: every case) and `event` (a name), in any order; one
/// window a row. A log, as a campaign records it: columns `time` and `event`, optionally `case`;
/// each row an event's name and an on/off word ("Lid Opened", "Lid Closed", "door on", "stop"),
/// a window from each on to the next off of the same name (to the end of the case when none
/// follows; from its start for an off with no on before it). A log's times are s from the start
/// of the case, or UNIX times (any time of 1e8 or more: s, ms, us or ns by magnitude) placed in
/// each case by place_events(). `cases` are the model's case names (empty: not checked). Throws
/// lang::CsvError naming the row and column of a missing column, a bad number or word, an
/// unknown case, end <= start, a negative start, or a window overlapping another of the same
/// event and case.
std::vector<EventWindow> parse_events(const std::string& text, const std::string& path,
                                      const std::vector<std::string>& cases);
/// Reads and parses an events file; throws lang::CsvError (row 0 when it cannot be read).
std::vector<EventWindow> read_events(const std::string& path,
                                     const std::vector<std::string>& cases);
/// The windows of every case: windows of a log placed in each case by its clock (UNIX times by the
/// case's epoch, every window cut to the case's duration, a case without an epoch receiving none
/// of the UNIX ones); other windows unchanged. Throws lang::CsvError (row 0) naming `path` when a
/// log's UNIX times fall in no case.
std::vector<EventWindow> place_events(const std::vector<EventWindow>& events,
                                      const std::vector<CaseClock>& cases, const std::string& path);
/// The event names, in order of first appearance.
std::vector<std::string> event_names(const std::vector<EventWindow>& events);
/// When `event` is on in case `case_name` (its own windows and every-case ones; with an empty
/// `case_name`, only every-case ones): a step signal, 1 while on, 0 otherwise.
lang::Signal event_schedule(const std::vector<EventWindow>& events, const std::string& case_name,
                            const std::string& event);

} // namespace thermnet
