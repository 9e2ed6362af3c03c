#pragma once
/// A self-contained HTML report page (diagnose --html, calibrate --html): escaped text, tables,
/// code and figures inlined as SVG under one style sheet for the screen and for A4 paper, with a
/// content security policy that forbids every network request and every script.

#include "plot/figure.hpp"

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace thermnet::plot {

/// Text made safe for HTML content or a quoted attribute: & < > " ' escaped, control characters
/// and invalid UTF-8 replaced (what a model file holds is untrusted).
std::string html_escape(std::string_view text);

/// How a table column is aligned.
enum class Align {
  left, ///< text
  right ///< numbers
};

/// A table of plain-text cells (escaped when written).
struct HtmlTable {
  std::string caption;                        ///< shown above it (may be empty)
  std::vector<std::string> head;              ///< column headings
  std::vector<Align> align;                   ///< per column (missing ones: left)
  std::vector<std::vector<std::string>> rows; ///< the cells, row by row
};

/// Attributes of an element: names chosen by the program, values escaped when written.
using HtmlAttributes = std::vector<std::pair<std::string, std::string>>;

/// An HTML page being built. Every text argument is plain text and is escaped; nothing a caller
/// passes becomes markup.
class HtmlPage {
public:
  /// A page titled `title` (the window title and the top heading).
  explicit HtmlPage(std::string title);
  /// Opens a section (a heading one level below the enclosing section's); `id` is its anchor
  /// (letters, digits, '-', '_'; listed in the contents when at the top level).
  void open_section(const std::string& id, std::string_view heading,
                    const HtmlAttributes& attributes = {});
  /// Closes the innermost open section.
  void close_section();
  /// A paragraph; `cls` is an optional class ("note", "lead").
  void paragraph(std::string_view text, std::string_view cls = {});
  /// A list of "term: description" pairs.
  void facts(const std::vector<std::pair<std::string, std::string>>& items);
  /// A bulleted list.
  void list(const std::vector<std::string>& items);
  /// A table.
  void table(const HtmlTable& t);
  /// Preformatted text (model lines), with an optional caption above it.
  void code(std::string_view text, std::string_view caption = {},
            const HtmlAttributes& attributes = {});
  /// A figure inlined as SVG with a caption; `name` goes to its data-plot attribute.
  void figure(Figure fig, std::string_view caption, std::string_view name);
  /// The whole document (closes the sections left open).
  std::string str() const;

private:
  std::string title_;
  std::string body_;
  std::vector<std::pair<std::string, std::string>> contents_; // top-level (id, heading)
  int depth_ = 0;
  int figures_ = 0;
};

} // namespace thermnet::plot
