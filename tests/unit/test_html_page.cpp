#include "plot/html_page.hpp"
#include "plot/svg_plot.hpp"

#include <doctest/doctest.h>

#include <string>

using namespace thermnet::plot;

namespace {

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1))
    ++n;
  return n;
}

Figure one_panel() {
  Figure fig;
  Panel p;
  p.x_label = "time [s]";
  p.y_label = "T [°C]";
  Series s;
  s.label = "a";
  s.x = {0, 1, 2};
  s.y = {1, 2, 3};
  p.series.push_back(s);
  fig.panels.push_back(p);
  return fig;
}

} // namespace

TEST_CASE("html_escape makes markup, quotes and control characters plain text") {
  CHECK(html_escape("<script>alert('x')</script> & \"y\"") ==
        "&lt;script&gt;alert(&apos;x&apos;)&lt;/script&gt; &amp; &quot;y&quot;");
  CHECK(html_escape("a\x01"
                    "b") == "a b");
  CHECK(html_escape("bad \xff byte") == "bad \xEF\xBF\xBD byte");
  CHECK(html_escape("°C ± 1") == "°C ± 1");
}

TEST_CASE("an HtmlPage escapes every text it is given and forbids every request") {
  HtmlPage page("m <b>&");
  page.open_section("run\"><x", "Run <i>", {{"data-kind", "k\"><script>"}});
  page.paragraph("<script>p</script>");
  page.facts({{"<dt>", "<dd>"}});
  page.list({"<li>"});
  page.table({"<cap>", {"<th>"}, {Align::right}, {{"<td>&"}}});
  page.code("line <1>\n\tline 2", "<caption>", {{"data-rank", "1"}});
  const std::string s = page.str(); // the open section is closed
  CHECK(s.find("<script") == std::string::npos);
  CHECK(s.find("<b>") == std::string::npos);
  CHECK(s.find("<title>m &lt;b&gt;&amp;</title>") != std::string::npos);
  CHECK(s.find("<section id=\"runx\" data-kind=\"k&quot;&gt;&lt;script&gt;\">") !=
        std::string::npos);
  CHECK(s.find("<td class=\"num\">&lt;td&gt;&amp;</td>") != std::string::npos);
  CHECK(s.find("<pre data-rank=\"1\"><code>line &lt;1&gt;\n line 2</code></pre>") !=
        std::string::npos);
  CHECK(count(s, "<section") == count(s, "</section>"));
  CHECK(s.find("default-src 'none'") != std::string::npos);
  CHECK(s.find("@media print") != std::string::npos);
}

TEST_CASE("figures inlined in one page have ids of their own and no XML declaration") {
  HtmlPage page("figures");
  page.figure(one_panel(), "first", "one");
  page.figure(one_panel(), "second", "two");
  const std::string s = page.str();
  CHECK(s.find("<?xml") == std::string::npos);
  CHECK(count(s, "<svg") == 2);
  CHECK(count(s, "id=\"f1-clip0\"") == 1);
  CHECK(count(s, "id=\"f2-clip0\"") == 1);
  CHECK(s.find("url(#f1-clip0)") != std::string::npos);
  CHECK(s.find("url(#f2-clip0)") != std::string::npos);
  CHECK(s.find("data-plot=\"two\"") != std::string::npos);
}

TEST_CASE("a figure's id prefix keeps only id characters; without one the ids are unchanged") {
  Figure fig = one_panel();
  CHECK(render_svg(fig).find("id=\"clip0\"") != std::string::npos);
  fig.id_prefix = "a\"><b-";
  const std::string svg = render_svg(fig);
  CHECK(svg.find("id=\"ab-clip0\"") != std::string::npos);
  CHECK(svg.find("url(#ab-clip0)") != std::string::npos);
}
