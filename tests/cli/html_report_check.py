#!/usr/bin/env python3
"""Checks a report page of `thermnet diagnose --html` or `calibrate --html` against the --json
report of the same run: every finding (its section, kind, nodes and the lines that add it), every
alternative and rejected candidate, every measured node of the baseline, every whiteness series
and every plot is on the page; the page is self-contained (nothing it would fetch, no script) and
every figure is an inline SVG with axes and a legend.

Usage: html_report_check.py diagnose|calibrate PAGE.html REPORT.json
Prints one line per failed check and exits 1 if any failed (standard library only).
"""
import html.parser
import json
import re
import sys


class Page(html.parser.HTMLParser):
    """The parts of the page the checks read."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack = []          # open elements: (tag, attrs)
        self.sections = []       # attrs of every <section>
        self.figures = []        # {'name', 'svg': count, 'paths', 'texts'}
        self.pres = []           # (attrs, text) of every <pre>
        self.cells = []          # text of every <td>
        self.text = []           # all text
        self.tags = set()
        self.attr_values = []    # (tag, name, value)
        self._pre = None
        self._td = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.add(tag)
        for name, value in attrs:
            self.attr_values.append((tag, name, value or ""))
        if tag == "section":
            self.sections.append(a)
        if tag == "figure":
            self.figures.append({"name": a.get("data-plot", ""), "svg": 0, "paths": 0,
                                 "texts": []})
        if tag == "svg" and self.figures:
            self.figures[-1]["svg"] += 1
        if tag == "path" and self.figures:
            self.figures[-1]["paths"] += 1
        if tag == "pre":
            self._pre = (a, [])
        if tag == "td":
            self._td = []
        self.stack.append(tag)

    def handle_endtag(self, tag):
        if tag == "pre" and self._pre is not None:
            self.pres.append((self._pre[0], "".join(self._pre[1])))
            self._pre = None
        if tag == "td" and self._td is not None:
            self.cells.append("".join(self._td))
            self._td = None
        if tag in self.stack:
            while self.stack and self.stack.pop() != tag:
                pass

    def handle_data(self, data):
        self.text.append(data)
        if self._pre is not None:
            self._pre[1].append(data)
        if self._td is not None:
            self._td.append(data)
        if self.stack and self.stack[-1] == "text" and self.figures:
            self.figures[-1]["texts"].append(data)


failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def self_contained(raw, page):
    """Nothing the page would fetch and nothing it would run."""
    check("<script" not in raw.lower(), "no <script element anywhere")
    check("script" not in page.tags, "no script element parsed")
    for tag, name, value in page.attr_values:
        if name in ("src", "srcset", "data", "action", "formaction", "poster", "background"):
            failures.append(f"attribute {name}= on <{tag}> ({value[:60]})")
        if name in ("href", "xlink:href") and not value.startswith("#"):
            failures.append(f"{name}= that is not an anchor on <{tag}> ({value[:60]})")
        if name.startswith("on"):
            failures.append(f"event handler {name}= on <{tag}>")
        if name == "xmlns" and value != "http://www.w3.org/2000/svg":
            failures.append(f"unexpected namespace {value[:60]}")
    # Every URL in the text: only the SVG namespace (an identifier, never fetched).
    for url in re.findall(r"(?:https?|ftp|file)://[^\s\"'<>)]*", raw, re.IGNORECASE):
        if url != "http://www.w3.org/2000/svg":
            failures.append(f"URL in the page: {url[:80]}")
    for pattern in (r"url\((?!#)", r"@import", r"@font-face", r"<link", r"<iframe", r"<object",
                    r"<embed", r"<img", r"<meta http-equiv=\"refresh"):
        if re.search(pattern, raw, re.IGNORECASE):
            failures.append(f"page holds {pattern}")
    check("Content-Security-Policy" in raw and "default-src 'none'" in raw,
          "a content security policy that forbids every request")


def figures_ok(page, wanted):
    names = [f["name"] for f in page.figures]
    for name in wanted:
        check(name in names, f"figure data-plot={name} on the page (figures: {names})")
    for f in page.figures:
        check(f["svg"] == 1 and f["paths"] > 0, f"figure {f['name']}: one inline SVG with paths")
        texts = " ".join(f["texts"])
        # axes with units and a legend: an axis label with a unit in brackets and legend text
        check(re.search(r"\[[^\]]+\]", texts) is not None,
              f"figure {f['name']}: an axis label with its unit")


def main():
    kind, page_path, json_path = sys.argv[1:4]
    raw = open(page_path, encoding="utf-8").read()
    report = json.load(open(json_path, encoding="utf-8"))
    page = Page()
    page.feed(raw)
    page.close()
    text = " ".join(" ".join(page.text).split())
    cells = set(c.strip() for c in page.cells)
    self_contained(raw, page)
    check(raw.startswith("<!DOCTYPE html>"), "an HTML5 document")
    check("@media print" in raw and "size: A4" in raw, "a print style sheet for A4")
    check("thermnet" in text and "version" in text, "thermnet's version named")
    check(re.search(r"\d{4}-\d\d-\d\d \d\d:\d\d UTC", text) is not None, "the date")
    check(f"thermnet {kind}" in text, "the command line")
    if kind == "diagnose":
        findings = [s for s in page.sections if "finding" in s.get("class", "").split()]
        check(len(findings) == len(report["findings"]),
              f"{len(report['findings'])} finding sections (found {len(findings)})")
        for f in report["findings"]:
            sec = [s for s in findings if s.get("data-rank") == str(f["rank"])]
            check(len(sec) == 1 and sec[0].get("data-kind") == f["kind"] and
                  sec[0].get("data-nodes") == ",".join(f["nodes"]),
                  f"finding {f['rank']} ({f['kind']} {f['nodes']}) has its section")
            lines = [t for a, t in page.pres if a.get("data-rank") == str(f["rank"])]
            check(len(lines) == 1, f"finding {f['rank']}: the lines that add it")
            if lines:
                for line in f["statement"].splitlines():
                    check(line in lines[0], f"finding {f['rank']}: statement line {line!r}")
                for case, stmts in f["case_statements"].items():
                    check(f"inside case {case}" in lines[0],
                          f"finding {f['rank']}: the lines of case {case}")
                    for line in stmts.splitlines():
                        check(line in lines[0], f"finding {f['rank']}: case line {line!r}")
            for name in f["values"]:
                check(name in cells, f"finding {f['rank']}: fitted parameter {name} in a table")
            for c in f.get("candidates", [])[1:]:
                check(any(c["kind"] in cell and ", ".join(c["nodes"]) in cell for cell in cells),
                      f"finding {f['rank']}: rival {c['kind']} {c['nodes']} in the ambiguity set")
        for group in ("alternatives", "rejected"):
            for f in report.get(group, []):
                check(any(cell.startswith(f["kind"]) and ", ".join(f["nodes"]) in cell
                          for cell in cells), f"{group}: {f['kind']} {f['nodes']} on the page")
        for node in report["baseline"]["nodes"]:
            check(node in cells, f"baseline node {node} in the baseline table")
        wanted = ["baseline", "whiteness"] + (["before-after"] if report["findings"] else [])
        figures_ok(page, wanted)
        pred = report.get("prediction")
        if pred:
            series = pred["whiteness_after"] if report["findings"] else pred["whiteness_before"]
            for s in series:
                check(s["node"] in cells and s["case"] in cells,
                      f"whiteness series {s['node']} / {s['case']} in the table")
    else:
        for name, value in report["params"].items():
            check(name in cells, f"param {name} in the parameter table")
        for case in report["cases"]:
            check(case in cells, f"case {case} in the fit per case")
        wanted = ["fit", "whiteness"] if report["found"] else []
        if report["method"] in ("mc", "lhs", "ga") and report["found"]:
            wanted.append("convergence")
        figures_ok(page, wanted)
        if report.get("whiteness"):
            for s in report["whiteness"]:
                check(s["node"] in cells and s["case"] in cells,
                      f"whiteness series {s['node']} / {s['case']} in the table")
    for f in failures:
        print("html_report_check:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
