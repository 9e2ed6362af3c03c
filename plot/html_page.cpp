#include "plot/html_page.hpp"

#include "plot/svg_plot.hpp"
#include "plot/text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace thermnet::plot {
namespace {

/// No request leaves the page (default-src 'none'), no script runs; the inline style sheet and
/// inline SVG are all it uses.
constexpr const char* kSecurityPolicy =
    "default-src 'none'; style-src 'unsafe-inline'; img-src data:; base-uri 'none'; "
    "form-action 'none'";

/// Screen: a readable column on a laptop; print: A4 with figures kept whole. Only system fonts.
constexpr const char* kStyle = R"css(
:root { color-scheme: light; }
body { font-family: system-ui, -apple-system, "Segoe UI", "Liberation Sans", "DejaVu Sans",
       Arial, sans-serif; font-size: 15px; line-height: 1.45; color: #1a1a1a; background: #fff;
       max-width: 64rem; margin: 0 auto; padding: 1rem 1.5rem 3rem; }
h1 { font-size: 1.6rem; margin: 0.5rem 0 0.75rem; }
h2 { font-size: 1.3rem; margin: 2rem 0 0.5rem; padding-bottom: 0.2rem;
     border-bottom: 2px solid #0072B2; }
h3 { font-size: 1.1rem; margin: 1.5rem 0 0.4rem; }
h4 { font-size: 1rem; margin: 1rem 0 0.3rem; }
nav ol { columns: 2; margin: 0.3rem 0 1rem; }
dl.facts { display: grid; grid-template-columns: max-content 1fr; gap: 0.15rem 1rem;
           margin: 0.5rem 0; }
dl.facts dt { font-weight: 600; }
dl.facts dd { margin: 0; overflow-wrap: anywhere; }
p.note { color: #444; font-size: 0.92em; border-left: 3px solid #E69F00; padding-left: 0.6rem; }
p.lead { font-size: 1.05em; }
table { border-collapse: collapse; margin: 0.4rem 0 1rem; font-size: 0.92em; }
caption { text-align: left; font-weight: 600; padding-bottom: 0.2rem; }
th, td { border: 1px solid #bbb; padding: 0.2rem 0.5rem; vertical-align: top; }
th { background: #eef3f8; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
.wide { overflow-x: auto; }
pre { background: #f6f6f6; border: 1px solid #ddd; padding: 0.5rem 0.7rem; overflow-x: auto;
      font-size: 0.88em; white-space: pre-wrap; overflow-wrap: anywhere; }
.code-caption { font-weight: 600; margin: 0.6rem 0 0.2rem; }
figure { margin: 0.8rem 0 1.2rem; }
figure svg { display: block; max-width: 100%; height: auto; }
figcaption { font-size: 0.9em; color: #333; margin-top: 0.3rem; }
section.finding { border-left: 4px solid #009E73; padding-left: 0.9rem; margin-top: 1.5rem; }
footer { margin-top: 2.5rem; font-size: 0.85em; color: #555; }
@page { size: A4; margin: 14mm 12mm; }
@media print {
  body { font-size: 10pt; max-width: none; padding: 0; }
  nav { display: none; }
  h2, h3, h4, .code-caption, caption { break-after: avoid; }
  figure, tr, pre, dl.facts { break-inside: avoid; }
  section.finding { break-before: page; }
  .wide { overflow: visible; }
  a { color: inherit; text-decoration: none; }
}
)css";

/// An id made of letters, digits, '-' and '_' only.
std::string clean_id(std::string_view id) {
  std::string out;
  for (const char c : id)
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') out += c;
  return out;
}

std::string attributes_text(const HtmlAttributes& attributes) {
  std::string s;
  for (const auto& [name, value] : attributes)
    s += fmt::format(" {}=\"{}\"", clean_id(name), html_escape(value));
  return s;
}

} // namespace

std::string html_escape(std::string_view text) {
  std::string out;
  const std::string clean = sanitize(text);
  out.reserve(clean.size());
  append_escaped(out, clean);
  return out;
}

HtmlPage::HtmlPage(std::string title) : title_(std::move(title)) {}

void HtmlPage::open_section(const std::string& id, std::string_view heading,
                            const HtmlAttributes& attributes) {
  const std::string anchor = clean_id(id);
  if (depth_ == 0) contents_.emplace_back(anchor, std::string(heading));
  ++depth_;
  const int level = std::min(depth_ + 1, 6);
  body_ += fmt::format("<section id=\"{}\"{}>\n<h{}>{}</h{}>\n", anchor,
                       attributes_text(attributes), level, html_escape(heading), level);
}

void HtmlPage::close_section() {
  if (depth_ == 0) return;
  --depth_;
  body_ += "</section>\n";
}

void HtmlPage::paragraph(std::string_view text, std::string_view cls) {
  if (cls.empty())
    body_ += fmt::format("<p>{}</p>\n", html_escape(text));
  else
    body_ += fmt::format("<p class=\"{}\">{}</p>\n", clean_id(cls), html_escape(text));
}

void HtmlPage::facts(const std::vector<std::pair<std::string, std::string>>& items) {
  body_ += "<dl class=\"facts\">\n";
  for (const auto& [term, text] : items)
    body_ += fmt::format("<dt>{}</dt><dd>{}</dd>\n", html_escape(term), html_escape(text));
  body_ += "</dl>\n";
}

void HtmlPage::list(const std::vector<std::string>& items) {
  body_ += "<ul>\n";
  for (const auto& item : items)
    body_ += fmt::format("<li>{}</li>\n", html_escape(item));
  body_ += "</ul>\n";
}

void HtmlPage::table(const HtmlTable& t) {
  body_ += "<div class=\"wide\"><table>\n";
  if (!t.caption.empty()) body_ += fmt::format("<caption>{}</caption>\n", html_escape(t.caption));
  body_ += "<thead><tr>";
  for (const auto& h : t.head)
    body_ += fmt::format("<th scope=\"col\">{}</th>", html_escape(h));
  body_ += "</tr></thead>\n<tbody>\n";
  for (const auto& row : t.rows) {
    body_ += "<tr>";
    for (std::size_t c = 0; c < row.size(); ++c) {
      const bool right = c < t.align.size() && t.align[c] == Align::right;
      body_ += right ? "<td class=\"num\">" : "<td>";
      body_ += html_escape(row[c]) + "</td>";
    }
    body_ += "</tr>\n";
  }
  body_ += "</tbody></table></div>\n";
}

void HtmlPage::code(std::string_view text, std::string_view caption,
                    const HtmlAttributes& attributes) {
  if (!caption.empty())
    body_ += fmt::format("<p class=\"code-caption\">{}</p>\n", html_escape(caption));
  // Line breaks and tabs are kept (sanitize would turn them into spaces).
  std::string escaped;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    std::string line(text.substr(start, end - start));
    for (char& c : line)
      if (c == '\t') c = ' ';
    escaped += html_escape(line);
    if (end < text.size()) escaped += '\n';
    start = end + 1;
  }
  body_ += fmt::format("<pre{}><code>{}</code></pre>\n", attributes_text(attributes), escaped);
}

void HtmlPage::figure(Figure fig, std::string_view caption, std::string_view name) {
  fig.id_prefix = fmt::format("f{}-", ++figures_);
  std::string svg = render_svg(fig);
  // Inline SVG needs no XML declaration.
  if (svg.rfind("<?xml", 0) == 0) svg.erase(0, svg.find('\n') + 1);
  body_ += fmt::format("<figure class=\"plot\" data-plot=\"{}\">\n{}<figcaption>{}</figcaption>\n"
                       "</figure>\n",
                       html_escape(name), svg, html_escape(caption));
}

std::string HtmlPage::str() const {
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  s += fmt::format("<meta http-equiv=\"Content-Security-Policy\" content=\"{}\">\n",
                   kSecurityPolicy);
  s += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  s += fmt::format("<title>{}</title>\n<style>{}</style>\n</head>\n<body>\n", html_escape(title_),
                   kStyle);
  s += fmt::format("<h1>{}</h1>\n", html_escape(title_));
  if (contents_.size() > 1) {
    s += "<nav aria-label=\"contents\"><ol>\n";
    for (const auto& [id, heading] : contents_)
      s += fmt::format("<li><a href=\"#{}\">{}</a></li>\n", id, html_escape(heading));
    s += "</ol></nav>\n";
  }
  s += body_;
  for (int d = depth_; d > 0; --d)
    s += "</section>\n";
  s += "</body>\n</html>\n";
  return s;
}

} // namespace thermnet::plot
