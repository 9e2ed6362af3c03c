#include "plot/svg_plot.hpp"

#include "plot/panel.hpp"
#include "plot/svg_writer.hpp"
#include "plot/text.hpp"

#include <algorithm>
#include <cctype>
#include <string>

namespace thermnet::plot {
namespace {

constexpr const char* kFontFamily =
    "Arial, Helvetica, 'Liberation Sans', 'DejaVu Sans', sans-serif";
constexpr double kFigureTitleFont = 16;

} // namespace

std::string render_svg(const Figure& fig) {
  const double width = std::clamp(fig.width, 240, 20000);
  const double panel_h = std::clamp(fig.panel_height, 160, 20000);
  const int n = static_cast<int>(fig.panels.size());
  const int cols = std::clamp(fig.columns, 1, std::max(1, n));
  const int rows = (n + cols - 1) / cols;
  const std::string title = sanitize(fig.title);
  const double title_h = title.empty() ? 0 : kFigureTitleFont + 18;
  const double height = std::max(title_h + rows * panel_h, 60.0);

  SvgWriter o;
  o.s.reserve(64 * 1024);
  o.s += "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n";
  o.f(R"(<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{0}" height="{1}" )"
      R"(viewBox="0 0 {0} {1}" font-family="{2}" font-size="12">)"
      "\n",
      n1(width), n1(height), kFontFamily);
  if (!title.empty()) {
    o.s += "<title>";
    o.text(title);
    o.s += "</title>\n";
  }
  o.f(R"(<rect x="0" y="0" width="{}" height="{}" fill="#ffffff"/>)"
      "\n",
      n1(width), n1(height));
  if (!title.empty()) {
    o.f(R"(<text x="{}" y="{}" text-anchor="middle" font-size="{}" font-weight="bold" fill="#111111">)",
        n1(width / 2), n1(8 + kFigureTitleFont), n1(kFigureTitleFont));
    o.text(fit_text(title, width - 16, kFigureTitleFont, true));
    o.s += "</text>\n";
  }
  std::string prefix;
  for (const char c : fig.id_prefix)
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') prefix += c;
  const double cell_w = width / cols;
  for (int i = 0; i < n; ++i) {
    const Rect cell{(i % cols) * cell_w, title_h + (i / cols) * panel_h, cell_w, panel_h};
    render_panel(o, fig.panels[static_cast<std::size_t>(i)], prefix + "clip" + std::to_string(i),
                 cell);
  }
  o.s += "</svg>\n";
  return o.s;
}

} // namespace thermnet::plot
