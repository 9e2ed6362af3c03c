// Unit tests of lang/source and lang/diagnostics: line mapping, the engine, and the three
// renderers (golden strings for text, field values for JSON and SARIF), plus typo matching.

#include "lang/diagnostics.hpp"
#include "lang/source.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

using namespace thermnet::lang;

namespace {

// The byte range of the `nth` occurrence of `needle` in `text` (0-based occurrence).
Span span_of(FileId file, const std::string& text, const std::string& needle, int nth = 0) {
  std::size_t pos = text.find(needle);
  for (int i = 0; i < nth && pos != std::string::npos; ++i)
    pos = text.find(needle, pos + 1);
  REQUIRE(pos != std::string::npos);
  return Span{file, static_cast<std::uint32_t>(pos),
              static_cast<std::uint32_t>(pos + needle.size())};
}

Span point(FileId file, std::size_t offset) {
  return Span{file, static_cast<std::uint32_t>(offset), static_cast<std::uint32_t>(offset)};
}

// A model whose line 12 is the statement of the contract's example.
const std::string kStatement = "    conduction g1 lens1 lens3 k = 1 L = 0.01 A = 3e-4";

std::string example_model() {
  std::string text = "model lens_stack {\n";
  for (int i = 2; i <= 11; ++i)
    text += "  # line " + std::to_string(i) + "\n";
  text += kStatement + "\n";
  text += "}\n";
  return text;
}

} // namespace

// -----------------------------------------------------------------------------------------
// SourceManager

TEST_CASE("source: line_col counts lines and 1-based columns") {
  SourceManager sm;
  const FileId f = sm.add("a.tnet", "ab\ncd\n\nef");
  CHECK(sm.size() == 1);
  CHECK(sm.line_col(f, 0).line == 1);
  CHECK(sm.line_col(f, 0).column == 1);
  CHECK(sm.line_col(f, 1).column == 2);
  CHECK(sm.line_col(f, 2).line == 1); // the '\n' itself belongs to its line
  CHECK(sm.line_col(f, 2).column == 3);
  CHECK(sm.line_col(f, 3).line == 2);
  CHECK(sm.line_col(f, 3).column == 1);
  CHECK(sm.line_col(f, 6).line == 3);
  CHECK(sm.line_col(f, 7).line == 4);
  CHECK(sm.line_col(f, 8).column == 2);
  // Past the end clamps to the end.
  CHECK(sm.line_col(f, 9).line == 4);
  CHECK(sm.line_col(f, 9).column == 3);
  CHECK(sm.line_col(f, 1000).line == 4);
  CHECK(sm.line_col(f, 1000).column == 3);
  CHECK(sm.line_text(f, 1) == "ab");
  CHECK(sm.line_text(f, 3) == "");
  CHECK(sm.line_text(f, 4) == "ef");
  CHECK(sm.line_text(f, 0) == "");
  CHECK(sm.line_text(f, 5) == "");
}

TEST_CASE("source: CRLF and lone CR end lines; CR is not part of the text") {
  SourceManager sm;
  const FileId f = sm.add("crlf.tnet", "ab\r\ncd\r\nx\ry");
  CHECK(sm.line_text(f, 1) == "ab");
  CHECK(sm.line_text(f, 2) == "cd");
  CHECK(sm.line_text(f, 3) == "x");
  CHECK(sm.line_text(f, 4) == "y");
  CHECK(sm.line_col(f, 4).line == 2);
  CHECK(sm.line_col(f, 4).column == 1);
  // Both bytes of the terminator map just past the last character.
  CHECK(sm.line_col(f, 2).column == 3);
  CHECK(sm.line_col(f, 3).line == 1);
  CHECK(sm.line_col(f, 3).column == 3);
  CHECK(sm.line_col(f, 10).line == 4);
  CHECK(sm.line_col(f, 10).column == 1);
  CHECK(sm.line_col(f, 11).column == 2);
}

TEST_CASE("source: empty file and trailing newline") {
  SourceManager sm;
  const FileId e = sm.add("empty.tnet", "");
  CHECK(sm.line_col(e, 0).line == 1);
  CHECK(sm.line_col(e, 5).column == 1);
  CHECK(sm.line_text(e, 1) == "");
  const FileId t = sm.add("t.tnet", "a\n");
  CHECK(sm.line_col(t, 2).line == 2);
  CHECK(sm.line_col(t, 2).column == 1);
}

TEST_CASE("source: columns count UTF-8 code points") {
  SourceManager sm;
  const std::string text = "\xC3\xA9t\xC3\xA9 = 1 \xE2\x84\x83 x\n"; // "été = 1 ℃ x"
  const FileId f = sm.add("u.tnet", text);
  CHECK(sm.line_col(f, 2).column == 2);                                           // 't'
  CHECK(sm.line_col(f, static_cast<std::uint32_t>(text.find('x'))).column == 11); // after ℃
}

TEST_CASE("source: columns stay exact on long lines mixing 1- to 4-byte characters") {
  // Long enough for the word-at-a-time counting, with sequences straddling word borders.
  const std::string unit = "a\xC3\xA9\xE2\x84\x83\xF0\x9D\x84\x9E"; // a é ℃ 𝄞
  std::string text;
  for (int i = 0; i < 700; ++i)
    text += unit;
  SourceManager sm;
  const FileId f = sm.add("u.tnet", text);
  std::uint32_t expected = 1;
  bool all_ok = true;
  for (std::size_t off = 0; off <= text.size(); ++off) {
    if (off < text.size() && (static_cast<unsigned char>(text[off]) & 0xC0) == 0x80) continue;
    all_ok = all_ok && sm.line_col(f, static_cast<std::uint32_t>(off)).column == expected;
    ++expected;
  }
  CHECK(all_ok);
  CHECK(sm.line_col(f, static_cast<std::uint32_t>(text.size())).column == 4 * 700 + 1);
}

TEST_CASE("source: find by path") {
  SourceManager sm;
  sm.add("a.tnet", "x");
  sm.add("dir/b.tnet", "y");
  CHECK(sm.find("a.tnet") == 0);
  CHECK(sm.find("dir/b.tnet") == 1);
  CHECK(sm.find("c.tnet") == -1);
  CHECK(sm.path(1) == "dir/b.tnet");
  CHECK(sm.text(0) == "x");
}

TEST_CASE("source: a 100 MB file is indexed and queried") {
  std::string big;
  const std::string line = "conduction g lens1 lens2 k = 1 L = 0.01 A = 3e-4\n"; // 50 bytes
  big.reserve(100u * 1024u * 1024u + line.size());
  while (big.size() < 100u * 1024u * 1024u)
    big += line;
  const std::size_t lines = big.size() / line.size();
  SourceManager sm;
  const FileId f = sm.add("big.tnet", std::move(big));
  const auto last = static_cast<std::uint32_t>(sm.text(f).size() - 2);
  CHECK(sm.line_col(f, last).line == lines);
  CHECK(sm.line_col(f, last).column == line.size() - 1);
  CHECK(sm.line_text(f, static_cast<std::uint32_t>(lines / 2)) == line.substr(0, line.size() - 1));
}

// -----------------------------------------------------------------------------------------
// Kinds table

TEST_CASE("diagnostics: kinds table matches the .def file and every format is valid") {
  const std::vector<DiagId> ids = {
#define DIAG(id, sev, code, fmtstr) DiagId::id,
#include "lang/diagnostic_kinds.def"
#undef DIAG
  };
  for (DiagId id : ids) {
    const DiagKind& k = diag_kind(id);
    CHECK(std::string(k.code).size() > 0);
    CHECK_NOTHROW((void)fmt::format(fmt::runtime(k.format), "a", "b", "c", "d", "e"));
  }
  CHECK(std::string(diag_kind(DiagId::unknown_node).code) == "unknown-node");
  CHECK(diag_kind(DiagId::unknown_node).severity == Severity::error);
  CHECK(diag_kind(DiagId::did_you_mean).severity == Severity::note);
  CHECK(diag_kind(DiagId::isolated_node).severity == Severity::warning);
}

// -----------------------------------------------------------------------------------------
// render_text golden strings

TEST_CASE("render_text: the contract's example") {
  SourceManager sm;
  const std::string text = example_model();
  const FileId f = sm.add("model.tnet", text);
  DiagnosticEngine eng(sm);
  const Span stmt = span_of(f, text, "conduction");
  const Span name = span_of(f, text, "lens3");
  Diagnostic& d = eng.report(DiagId::unknown_node, stmt, name, "lens3");
  d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, "lens2"));
  CHECK(render_text(eng) == "model.tnet:12:5: error: unknown node 'lens3' [unknown-node]\n"
                            "    conduction g1 lens1 lens3 k = 1 L = 0.01 A = 3e-4\n"
                            "                        ^~~~~\n"
                            "model.tnet:12:5: note: did you mean 'lens2'?\n");
  CHECK(eng.error_count() == 1);
  CHECK(eng.warning_count() == 0);
}

TEST_CASE("render_text: without a mark the caret underlines `at`; warnings keep the code") {
  SourceManager sm;
  const std::string text = "node a\nnode bb\n";
  const FileId f = sm.add("m.tnet", text);
  DiagnosticEngine eng(sm);
  eng.report(DiagId::isolated_node, span_of(f, text, "bb"), std::nullopt, "bb");
  CHECK(render_text(eng) == "m.tnet:2:6: warning: node 'bb' has no links [isolated-node]\n"
                            "node bb\n"
                            "     ^~\n");
  CHECK(eng.warning_count() == 1);
}

TEST_CASE("render_text: a mark spanning lines is underlined to the end of its first line") {
  SourceManager sm;
  const std::string text = "x\ncase hot {\n  duration = 10 s\n";
  const FileId f = sm.add("m.tnet", text);
  DiagnosticEngine eng(sm);
  const Span open = span_of(f, text, "case");
  const Span block{f, open.begin, static_cast<std::uint32_t>(text.size())};
  eng.report(DiagId::unterminated_block, open, block, "case");
  CHECK(render_text(eng) ==
        "m.tnet:2:1: error: '{' of this case is never closed [unterminated-block]\n"
        "case hot {\n"
        "^~~~~~~~~~\n");
}

TEST_CASE("render_text: a zero-length mark at the end of a line gets a lone caret") {
  SourceManager sm;
  const std::string text = "node a\nconduction g1 a b k = \nnode b\n";
  const FileId f = sm.add("m.tnet", text);
  DiagnosticEngine eng(sm);
  const std::size_t eol = text.find(" \n") + 1;
  eng.report(DiagId::syntax_expected, point(f, eol), std::nullopt, "a value");
  CHECK(render_text(eng) == "m.tnet:2:23: error: expected a value [syntax]\n"
                            "conduction g1 a b k = \n"
                            "                      ^\n");
}

TEST_CASE("render_text: zero-length mark at the very end of a file without final newline") {
  SourceManager sm;
  const std::string text = "model m {";
  const FileId f = sm.add("m.tnet", text);
  DiagnosticEngine eng(sm);
  eng.report(DiagId::syntax_expected, point(f, text.size()), std::nullopt, "'}'");
  CHECK(render_text(eng) == "m.tnet:1:10: error: expected '}' [syntax]\n"
                            "model m {\n"
                            "         ^\n");
}

TEST_CASE("render_text: columns and carets count UTF-8 code points") {
  SourceManager sm;
  // "node été_1 # ℃" ; the mark is on the name with two 2-byte characters.
  const std::string text = "node \xC3\xA9t\xC3\xA9_1 # \xE2\x84\x83\nnode b\n";
  const FileId f = sm.add("u.tnet", text);
  DiagnosticEngine eng(sm);
  const Span name = span_of(f, text, "\xC3\xA9t\xC3\xA9_1");
  eng.report(DiagId::duplicate_name, name, std::nullopt, "node", "\xC3\xA9t\xC3\xA9_1");
  eng.report(DiagId::syntax_unexpected, span_of(f, text, "\xE2\x84\x83"), std::nullopt,
             "'\xE2\x84\x83'");
  CHECK(render_text(eng) ==
        "u.tnet:1:6: error: node '\xC3\xA9t\xC3\xA9_1' is already defined [duplicate-name]\n"
        "node \xC3\xA9t\xC3\xA9_1 # \xE2\x84\x83\n"
        "     ^~~~~\n"
        "u.tnet:1:14: error: unexpected '\xE2\x84\x83' [syntax]\n"
        "node \xC3\xA9t\xC3\xA9_1 # \xE2\x84\x83\n"
        "             ^\n");
}

TEST_CASE("render_text: tabs become single spaces so the caret stays aligned") {
  SourceManager sm;
  const std::string text = "\tnode\tx1\n";
  const FileId f = sm.add("t.tnet", text);
  DiagnosticEngine eng(sm);
  eng.report(DiagId::isolated_node, span_of(f, text, "x1"), std::nullopt, "x1");
  CHECK(render_text(eng) == "t.tnet:1:7: warning: node 'x1' has no links [isolated-node]\n"
                            " node x1\n"
                            "      ^~\n");
}

TEST_CASE("render_text: a note with its own location shows its snippet") {
  SourceManager sm;
  const std::string text = "node lens1\nnode lens2\nnode lens1\n";
  const FileId f = sm.add("model.tnet", text);
  DiagnosticEngine eng(sm);
  const Span second = span_of(f, text, "lens1", 1);
  const Span first = span_of(f, text, "lens1", 0);
  Diagnostic& d = eng.report(DiagId::duplicate_name, second, std::nullopt, "node", "lens1");
  d.notes.push_back(DiagnosticEngine::note(DiagId::previous_definition, first));
  CHECK(render_text(eng) ==
        "model.tnet:3:6: error: node 'lens1' is already defined [duplicate-name]\n"
        "node lens1\n"
        "     ^~~~~\n"
        "model.tnet:1:6: note: previous definition is here\n"
        "node lens1\n"
        "     ^~~~~\n");
}

TEST_CASE("render_text: a note in another file") {
  SourceManager sm;
  const std::string main = "include \"lib.tnet\"\nnode a\n";
  const std::string lib = "node a\n";
  const FileId m = sm.add("main.tnet", main);
  const FileId l = sm.add("lib/lib.tnet", lib);
  DiagnosticEngine eng(sm);
  Diagnostic& d =
      eng.report(DiagId::duplicate_name, span_of(m, main, "a"), std::nullopt, "node", "a");
  d.notes.push_back(DiagnosticEngine::note(DiagId::previous_definition, span_of(l, lib, "a")));
  CHECK(render_text(eng) == "main.tnet:2:6: error: node 'a' is already defined [duplicate-name]\n"
                            "node a\n"
                            "     ^\n"
                            "lib/lib.tnet:1:6: note: previous definition is here\n"
                            "node a\n"
                            "     ^\n");
}

TEST_CASE("render_text: file-less diagnostics name the hint or thermnet, without snippet") {
  SourceManager sm;
  DiagnosticEngine eng(sm);
  const DiagKind& k = diag_kind(DiagId::file_unreadable);
  eng.add(Diagnostic{k.severity,
                     k.code,
                     "cannot read file 'missing.tnet': No such file",
                     std::nullopt,
                     std::nullopt,
                     "missing.tnet",
                     {}});
  Diagnostic& e = eng.report(DiagId::file_unreadable, std::nullopt, std::nullopt, "x.tnet",
                             "Permission denied");
  e.notes.push_back(DiagnosticEngine::note(DiagId::note_text, std::nullopt, "check the path"));
  CHECK(render_text(eng) ==
        "missing.tnet: error: cannot read file 'missing.tnet': No such file [file-unreadable]\n"
        "thermnet: error: cannot read file 'x.tnet': Permission denied [file-unreadable]\n"
        "thermnet: note: check the path\n");
}

TEST_CASE("render_text: a very long line is shown as a window around the mark") {
  SourceManager sm;
  std::string text = "param p = 1";
  for (int i = 0; i < 300; ++i)
    text += " + 1";
  text += " + zz";
  for (int i = 0; i < 300; ++i)
    text += " + 1";
  text += "\n";
  const FileId f = sm.add("long.tnet", text);
  DiagnosticEngine eng(sm);
  const Span zz = span_of(f, text, "zz");
  eng.report(DiagId::unknown_name, zz, std::nullopt, "zz");
  const std::string out = render_text(eng);
  const std::string header =
      "long.tnet:1:1215: error: unknown const or param 'zz' [unknown-name]\n";
  REQUIRE(out.substr(0, header.size()) == header);
  const std::string rest = out.substr(header.size());
  const std::size_t nl = rest.find('\n');
  const std::string src = rest.substr(0, nl);
  const std::string caret = rest.substr(nl + 1);
  CHECK(src.substr(0, 3) == "...");
  CHECK(src.substr(src.size() - 3) == "...");
  CHECK(src.size() == 3 + 160 + 3);
  const std::size_t col = caret.find('^');
  CHECK(caret == std::string(col, ' ') + "^~\n");
  CHECK(src.substr(col, 2) == "zz");
}

TEST_CASE("render_text: a long line with the mark near its start has only a trailing ellipsis") {
  SourceManager sm;
  std::string text = "zz";
  for (int i = 0; i < 100; ++i)
    text += " + 1";
  const FileId f = sm.add("long.tnet", text);
  DiagnosticEngine eng(sm);
  eng.report(DiagId::unknown_name, span_of(f, text, "zz"), std::nullopt, "zz");
  const std::string out = render_text(eng);
  CHECK(out == "long.tnet:1:1: error: unknown const or param 'zz' [unknown-name]\n" +
                   text.substr(0, 160) + "...\n^~\n");
}

TEST_CASE("render_text: color adds ANSI escapes; off by default") {
  SourceManager sm;
  const std::string text = "node a\n";
  const FileId f = sm.add("m.tnet", text);
  DiagnosticEngine eng(sm);
  eng.report(DiagId::isolated_node, span_of(f, text, "a"), std::nullopt, "a");
  const std::string plain = render_text(eng);
  CHECK(plain.find('\x1b') == std::string::npos);
  const std::string colored = render_text(eng, true);
  CHECK(colored.find("\x1b[1;35mwarning: ") != std::string::npos);
  CHECK(colored.find("\x1b[1;32m^") != std::string::npos);
}

// -----------------------------------------------------------------------------------------
// Engine

TEST_CASE("engine: error limit keeps `limit` errors plus one too-many-errors") {
  SourceManager sm;
  const std::string text = "a b c d e f\n";
  const FileId f = sm.add("m.tnet", text);
  DiagnosticEngine eng(sm, 3);
  for (int i = 0; i < 3; ++i) {
    CHECK_FALSE(eng.saturated());
    eng.report(DiagId::unknown_node, point(f, static_cast<std::size_t>(2 * i)), std::nullopt, "x");
  }
  CHECK(eng.saturated());
  CHECK(eng.all().size() == 3);
  for (int i = 0; i < 5; ++i) {
    Diagnostic& sink = eng.report(DiagId::unknown_node, point(f, 8), std::nullopt, "dropped");
    // Attaching notes to a dropped diagnostic must be harmless.
    sink.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, "y"));
  }
  // Warnings are still accepted after saturation.
  eng.report(DiagId::isolated_node, point(f, 10), std::nullopt, "f");
  REQUIRE(eng.all().size() == 5);
  CHECK(eng.all()[3].code == "too-many-errors");
  CHECK(eng.all()[3].message == "too many errors (3); stopping");
  CHECK_FALSE(eng.all()[3].at.has_value());
  CHECK(eng.all()[4].code == "isolated-node");
  CHECK(eng.error_count() == 4);
  CHECK(eng.warning_count() == 1);
  for (const Diagnostic& d : eng.all())
    CHECK(d.message != "unknown node 'dropped'");
  CHECK(
      render_text(eng).find("thermnet: error: too many errors (3); stopping [too-many-errors]\n") !=
      std::string::npos);
}

TEST_CASE("engine: sort orders by file then offset, stably, file-less last") {
  SourceManager sm;
  const FileId a = sm.add("a.tnet", "0123456789");
  const FileId b = sm.add("b.tnet", "0123456789");
  DiagnosticEngine eng(sm, 100);
  eng.report(DiagId::note_text, point(b, 1), std::nullopt, "b1");
  eng.report(DiagId::note_text, point(a, 5), std::nullopt, "a5-first");
  eng.report(DiagId::note_text, std::nullopt, std::nullopt, "nowhere");
  eng.report(DiagId::note_text, point(a, 2), std::nullopt, "a2");
  eng.report(DiagId::note_text, point(a, 5), std::nullopt, "a5-second");
  eng.report(DiagId::note_text, point(b, 0), std::nullopt, "b0");
  eng.sort();
  std::vector<std::string> order;
  for (const Diagnostic& d : eng.all())
    order.push_back(d.message);
  CHECK(order == std::vector<std::string>{"a2", "a5-first", "a5-second", "b0", "b1", "nowhere"});
}

// -----------------------------------------------------------------------------------------
// JSON

TEST_CASE("render_json: fields, mark end and inherited note locations") {
  SourceManager sm;
  const std::string text = example_model();
  const FileId f = sm.add("model.tnet", text);
  DiagnosticEngine eng(sm);
  Diagnostic& d = eng.report(DiagId::unknown_node, span_of(f, text, "conduction"),
                             span_of(f, text, "lens3"), "lens3");
  d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, "lens2"));
  const DiagKind& k = diag_kind(DiagId::file_unreadable);
  eng.add(Diagnostic{k.severity,
                     k.code,
                     "cannot read file 'x.csv': gone",
                     std::nullopt,
                     std::nullopt,
                     "x.csv",
                     {}});

  const std::string out = render_json(eng);
  CHECK(out.substr(0, 4) == "[\n  ");
  CHECK(out.back() == '\n');
  const auto j = nlohmann::json::parse(out);
  REQUIRE(j.is_array());
  REQUIRE(j.size() == 2);
  CHECK(j[0]["file"] == "model.tnet");
  CHECK(j[0]["line"] == 12);
  CHECK(j[0]["column"] == 5);
  CHECK(j[0]["end_line"] == 12);
  CHECK(j[0]["end_column"] == 30);
  CHECK(j[0]["severity"] == "error");
  CHECK(j[0]["code"] == "unknown-node");
  CHECK(j[0]["message"] == "unknown node 'lens3'");
  REQUIRE(j[0]["notes"].size() == 1);
  CHECK(j[0]["notes"][0]["file"] == "model.tnet");
  CHECK(j[0]["notes"][0]["line"] == 12);
  CHECK(j[0]["notes"][0]["column"] == 5);
  CHECK(j[0]["notes"][0]["severity"] == "note");
  CHECK(j[0]["notes"][0]["code"] == "note");
  CHECK(j[0]["notes"][0]["message"] == "did you mean 'lens2'?");
  CHECK(j[1]["file"] == "x.csv");
  CHECK(j[1]["line"] == 1); // a whole-file diagnostic sits at the start: positions are 1-based
  CHECK(j[1]["column"] == 1);
  CHECK(j[1]["severity"] == "error");
  CHECK(j[1]["notes"].empty());
}

TEST_CASE("render_json: empty engine and invalid UTF-8 in messages") {
  SourceManager sm;
  DiagnosticEngine eng(sm);
  CHECK(render_json(eng) == "[]\n");
  eng.report(DiagId::unknown_node, std::nullopt, std::nullopt, "bad\xFF");
  const auto j = nlohmann::json::parse(render_json(eng));
  // Shown as Clang shows it, in every format (never raw, never silently replaced).
  CHECK(j[0]["message"] == "unknown node 'bad<FF>'");
}

// -----------------------------------------------------------------------------------------
// SARIF

TEST_CASE("render_sarif: required properties, rules, artifacts, regions and notes") {
  SourceManager sm;
  const std::string text = example_model();
  const FileId f = sm.add("models/model.tnet", text);
  DiagnosticEngine eng(sm);
  Diagnostic& d = eng.report(DiagId::unknown_node, span_of(f, text, "conduction"),
                             span_of(f, text, "lens3"), "lens3");
  d.notes.push_back(DiagnosticEngine::note(DiagId::did_you_mean, std::nullopt, "lens2"));
  eng.report(DiagId::isolated_node, span_of(f, text, "lens1"), std::nullopt, "lens1");
  eng.report(DiagId::unknown_node, span_of(f, text, "g1"), std::nullopt, "g1");
  eng.add(Diagnostic{Severity::error,
                     "file-unreadable",
                     "cannot read",
                     std::nullopt,
                     std::nullopt,
                     "data dir\\temps.csv",
                     {}});
  eng.report(DiagId::too_many_errors, std::nullopt, std::nullopt, 1);

  const auto log = nlohmann::json::parse(render_sarif(eng, "0.3.0"));
  CHECK(log["$schema"] == "https://json.schemastore.org/sarif-2.1.0.json");
  CHECK(log["version"] == "2.1.0");
  REQUIRE(log["runs"].size() == 1);
  const auto& run = log["runs"][0];
  CHECK(run["tool"]["driver"]["name"] == "thermnet");
  CHECK(run["tool"]["driver"]["version"] == "0.3.0");
  const auto& rules = run["tool"]["driver"]["rules"];
  REQUIRE(rules.size() == 4);
  CHECK(rules[0]["id"] == "unknown-node");
  CHECK(rules[1]["id"] == "isolated-node");
  CHECK(rules[2]["id"] == "file-unreadable");
  CHECK(rules[3]["id"] == "too-many-errors");
  REQUIRE(run["artifacts"].size() == 2);
  CHECK(run["artifacts"][0]["location"]["uri"] == "models/model.tnet");
  CHECK(run["artifacts"][1]["location"]["uri"] == "data%20dir/temps.csv");

  const auto& results = run["results"];
  REQUIRE(results.size() == 5);
  for (const auto& r : results) {
    CHECK(r.contains("message"));
    CHECK(r["message"].contains("text"));
    CHECK(r.contains("ruleId"));
    CHECK(rules[r["ruleIndex"].get<std::size_t>()]["id"] == r["ruleId"]);
  }
  const auto& r0 = results[0];
  CHECK(r0["ruleId"] == "unknown-node");
  CHECK(r0["level"] == "error");
  CHECK(r0["message"]["text"] == "unknown node 'lens3'");
  const auto& pl = r0["locations"][0]["physicalLocation"];
  CHECK(pl["artifactLocation"]["uri"] == "models/model.tnet");
  CHECK(pl["artifactLocation"]["index"] == 0);
  CHECK(pl["region"]["startLine"] == 12);
  CHECK(pl["region"]["startColumn"] == 5);
  CHECK(pl["region"]["endLine"] == 12);
  CHECK(pl["region"]["endColumn"] == 30);
  REQUIRE(r0["relatedLocations"].size() == 1);
  CHECK(r0["relatedLocations"][0]["message"]["text"] == "did you mean 'lens2'?");
  CHECK(r0["relatedLocations"][0]["physicalLocation"]["region"]["startLine"] == 12);

  CHECK(results[1]["level"] == "warning");
  CHECK(results[1]["locations"][0]["physicalLocation"]["region"]["startColumn"] == 19);
  CHECK(results[1]["locations"][0]["physicalLocation"]["region"]["endColumn"] == 24);
  CHECK_FALSE(results[1].contains("relatedLocations"));

  // File-less: an artifact location from the hint but no region; without hint no location.
  CHECK(results[3]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] ==
        "data%20dir/temps.csv");
  CHECK_FALSE(results[3]["locations"][0]["physicalLocation"].contains("region"));
  CHECK_FALSE(results[4].contains("locations"));
}

TEST_CASE("render_sarif: absolute paths become file URIs; empty log is valid") {
  SourceManager sm;
  const FileId f = sm.add("/home/u/m.tnet", "node a\n");
  DiagnosticEngine eng(sm);
  auto empty = nlohmann::json::parse(render_sarif(eng, ""));
  CHECK(empty["runs"][0]["results"].empty());
  CHECK(empty["runs"][0]["tool"]["driver"]["rules"].empty());
  CHECK_FALSE(empty["runs"][0]["tool"]["driver"].contains("version"));
  eng.report(DiagId::isolated_node, point(f, 5), std::nullopt, "a");
  auto log = nlohmann::json::parse(render_sarif(eng, "1"));
  CHECK(log["runs"][0]["artifacts"][0]["location"]["uri"] == "file:///home/u/m.tnet");
  const auto& region = log["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["region"];
  CHECK(region["startColumn"] == 6);
  CHECK(region["endColumn"] == 6);
}

// -----------------------------------------------------------------------------------------
// closest_match

TEST_CASE("closest_match: plausible typos only") {
  const std::vector<std::string> nodes = {"lens1", "lens2", "housing", "ambient"};
  // On ties the nearest differing character wins, as in the contract example (lens3 -> lens2).
  CHECK(closest_match("lens3", nodes) == std::optional<std::string>("lens2"));
  CHECK(closest_match("lens0", nodes) == std::optional<std::string>("lens1"));
  CHECK(closest_match("lens3", {"housing", "lens2"}) == std::optional<std::string>("lens2"));
  const std::vector<std::string> kinds = {"conduction", "convection", "radiation", "heater"};
  CHECK(closest_match("condction", kinds) == std::optional<std::string>("conduction"));
  CHECK(closest_match("convcetion", kinds) == std::optional<std::string>("convection"));
  CHECK(closest_match("xyz", nodes) == std::nullopt);
  CHECK(closest_match("xyz", {}) == std::nullopt);
  CHECK(closest_match("", nodes) == std::nullopt);
  CHECK(closest_match("a", {"b"}) == std::nullopt); // distance must be below the length
  CHECK(closest_match("heatr", kinds) == std::optional<std::string>("heater"));
  // Case-insensitive comparison breaks ties between equally distant candidates.
  CHECK(closest_match("Lens2", {"Lens3", "lens2"}) == std::optional<std::string>("lens2"));
  // Absurd lengths are refused.
  CHECK(closest_match(std::string(65, 'a'), {std::string(65, 'a')}) == std::nullopt);
  CHECK(closest_match(std::string(64, 'a'), {std::string(64, 'a')}) ==
        std::optional<std::string>(std::string(64, 'a')));
}
