#pragma once
/// The words that mean on and off in measured files: a heater's `True`/`False` column, a relay's
/// `on`/`off`, an event log's "Lid Opened" and "Lid Closed".

#include <optional>
#include <string>

namespace thermnet::lang {

/// An on/off word as 1 or 0 (`True`/`False`, `on`/`off`, `yes`/`no`, `open`/`opened`,
/// `close`/`closed`, `start`/`started`, `stop`/`stopped`, any case), alone or last after a name
/// ("Lid Opened"); nullopt for any other text.
std::optional<double> on_off_word(const std::string& s);

} // namespace thermnet::lang
