// NODE DATA, CONDUCTOR DATA and SOURCE DATA lines of a SINDA/FLUINT deck.

#include "import/sinda_lines.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <cstdlib>

namespace thermnet::importer::sinda {

namespace {

/// True when a field is a keyword (GEN, SIV, SIM, ...) rather than a number or a node.
bool is_keyword(const Field& f) {
  return !f.text.empty() &&
         ((f.text[0] >= 'A' && f.text[0] <= 'Z') || (f.text[0] >= 'a' && f.text[0] <= 'z')) &&
         f.text.find('.') == std::string_view::npos;
}

/// The span from the first to the last field.
lang::Span fields_span(const std::vector<Field>& f) {
  return lang::Span{f.front().at.file, f.front().at.begin, f.back().at.end};
}

void expect_fields(const std::vector<Field>& f, std::size_t n, const SourceLine& line,
                   const char* form) {
  if (f.size() == n) return;
  const lang::Span at = f.empty() ? line.whole() : fields_span(f);
  throw ImportError(at, "bad-syntax",
                    fmt::format("expected {} fields ({}), found {}", n, form, f.size()));
}

/// The number of cards a GEN line makes, checked against the limit.
std::int64_t generated_count(const Field& f, std::size_t so_far) {
  const std::int64_t n = integer_field(f, "the number of generated items");
  if (n < 1) throw ImportError(f.at, "invalid-value", "GEN must generate at least one item");
  if (static_cast<std::uint64_t>(n) > max_cards - std::min(so_far, max_cards))
    throw ImportError(f.at, "too-large",
                      fmt::format("GEN generates {} items; a deck may hold at most {} nodes and "
                                  "{} conductors",
                                  n, max_cards, max_cards));
  return n;
}

/// A generated id, checked to stay within thermnet's index range.
std::int64_t generated_id(std::int64_t first, std::int64_t k, std::int64_t inc, const Field& at) {
  constexpr std::int64_t limit = 1'000'000'000'000'000;
  const long double v = static_cast<long double>(first) + static_cast<long double>(k) * inc;
  if (v < -limit || v > limit)
    throw ImportError(at.at, "invalid-value", "GEN generates ids beyond 10^15");
  return first + k * inc;
}

} // namespace

LineResult node_line(const SourceLine& line, const std::string& sub, Deck& deck) {
  const std::vector<Field> f = split_fields(line);
  if (f.empty()) return {};
  if (is_keyword(f[0])) {
    if (upper(f[0].text) != "GEN")
      return {LineUse::dropped, fmt::format("node data with the option {} (temperature- or "
                                            "time-dependent capacitance)",
                                            lang::excerpt_for_display(upper(f[0].text)))};
    expect_fields(f, 6, line, "GEN id, count, increment, T, C");
    const std::int64_t first = integer_field(f[1], "a node id");
    const std::int64_t n = generated_count(f[2], deck.nodes.size());
    const std::int64_t inc = integer_field(f[3], "the id increment");
    if (first == 0) throw ImportError(f[1].at, "invalid-value", "a node id may not be 0");
    if (inc == 0 && n > 1)
      throw ImportError(f[3].at, "invalid-value", "GEN with increment 0 repeats one node id");
    const double T = real_field(f[4]);
    const double C = real_field(f[5]);
    for (std::int64_t k = 0; k < n; ++k) {
      const std::int64_t id = generated_id(std::llabs(first), k, inc, f[3]);
      if (id <= 0) throw ImportError(f[3].at, "invalid-value", "GEN generates an id below 1");
      deck.nodes.push_back({sub, id, T, C, first < 0, line.whole(), f[4].at, f[5].at});
    }
    return {};
  }
  expect_fields(f, 3, line, "id, T, C");
  if (deck.nodes.size() >= max_cards)
    throw ImportError(line.whole(), "too-large",
                      fmt::format("more than {} nodes in the deck", max_cards));
  const std::int64_t id = integer_field(f[0], "a node id");
  if (id == 0) throw ImportError(f[0].at, "invalid-value", "a node id may not be 0");
  deck.nodes.push_back({sub, std::llabs(id), real_field(f[1]), real_field(f[2]), id < 0,
                        line.whole(), f[1].at, f[2].at});
  return {};
}

namespace {

/// A node of a conductor: a negative id marks a one-way conductor, which is not translated.
bool one_way(const NodeRef& r) {
  return r.id < 0;
}

} // namespace

LineResult conductor_line(const SourceLine& line, const std::string& sub, Deck& deck) {
  const std::vector<Field> f = split_fields(line);
  if (f.empty()) return {};
  if (is_keyword(f[0])) {
    if (upper(f[0].text) != "GEN")
      return {LineUse::dropped,
              fmt::format("conductor data with the option {} (temperature- or time-dependent "
                          "conductance)",
                          lang::excerpt_for_display(upper(f[0].text)))};
    expect_fields(f, 9, line, "GEN id, count, increment, a, a increment, b, b increment, G");
    const std::int64_t first = integer_field(f[1], "a conductor id");
    const std::int64_t n = generated_count(f[2], deck.conductors.size());
    const std::int64_t inc = integer_field(f[3], "the id increment");
    NodeRef a = node_field(f[4], sub);
    const std::int64_t a_inc = integer_field(f[5], "the node increment");
    NodeRef b = node_field(f[6], sub);
    const std::int64_t b_inc = integer_field(f[7], "the node increment");
    const double G = real_field(f[8]);
    if (first == 0) throw ImportError(f[1].at, "invalid-value", "a conductor id may not be 0");
    if (inc == 0 && n > 1)
      throw ImportError(f[3].at, "invalid-value", "GEN with increment 0 repeats one conductor id");
    if (one_way(a) || one_way(b))
      return {LineUse::dropped, "a one-way conductor (a negative node id)"};
    for (std::int64_t k = 0; k < n; ++k) {
      ConductorCard c{
          sub,    generated_id(std::llabs(first), k, inc, f[3]), first < 0, a, b, G, line.whole(),
          f[8].at};
      c.a.id = generated_id(a.id, k, a_inc, f[5]);
      c.b.id = generated_id(b.id, k, b_inc, f[7]);
      if (c.id <= 0 || c.a.id <= 0 || c.b.id <= 0)
        throw ImportError(line.whole(), "invalid-value", "GEN generates an id below 1");
      deck.conductors.push_back(std::move(c));
    }
    return {};
  }
  expect_fields(f, 4, line, "id, a, b, G");
  if (deck.conductors.size() >= max_cards)
    throw ImportError(line.whole(), "too-large",
                      fmt::format("more than {} conductors in the deck", max_cards));
  const std::int64_t id = integer_field(f[0], "a conductor id");
  if (id == 0) throw ImportError(f[0].at, "invalid-value", "a conductor id may not be 0");
  NodeRef a = node_field(f[1], sub);
  NodeRef b = node_field(f[2], sub);
  const double G = real_field(f[3]);
  if (one_way(a) || one_way(b))
    return {LineUse::dropped, "a one-way conductor (a negative node id)"};
  deck.conductors.push_back({sub, std::llabs(id), id < 0, a, b, G, line.whole(), f[3].at});
  return {};
}

LineResult source_line(const SourceLine& line, const std::string& sub, Deck& deck) {
  const std::vector<Field> f = split_fields(line);
  if (f.empty()) return {};
  if (is_keyword(f[0]))
    return {LineUse::dropped,
            fmt::format("source data with the option {} (a time- or temperature-dependent load)",
                        lang::excerpt_for_display(upper(f[0].text)))};
  expect_fields(f, 2, line, "id, Q");
  NodeRef node = node_field(f[0], sub);
  if (node.id < 0) throw ImportError(f[0].at, "invalid-value", "a node id may not be negative");
  deck.sources.push_back({node, real_field(f[1]), line.whole(), false});
  return {};
}

} // namespace thermnet::importer::sinda
