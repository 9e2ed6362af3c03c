#pragma once
/// Text in charts: valid UTF-8 without control characters, its estimated width, cutting it to fit
/// and escaping it for XML.

#include <string>
#include <string_view>

namespace thermnet::plot {

/// Valid UTF-8 with control characters replaced by spaces and invalid bytes by U+FFFD.
std::string sanitize(std::string_view s);

/// Estimated rendered width of (sanitised) text in px, erring on the generous side.
double text_width(std::string_view s, double font_size);

/// Valid UTF-8 cut to fit in `width` px at font_size, ending in an ellipsis when cut.
std::string truncate(std::string_view s, double width, double font_size);

/// Sanitised text cut to fit in width px at font_size (bold text is about 10 % wider).
std::string fit_text(std::string_view raw, double width, double font_size, bool bold = false);

/// Appends already sanitised text to `out`, escaped for XML content and attributes.
void append_escaped(std::string& out, std::string_view s);

/// Text escaped for XML content and attributes; control characters become spaces, bad UTF-8 U+FFFD.
std::string xml_escape(std::string_view text);

} // namespace thermnet::plot
