#include "import/spice_foster.hpp"

#include "lang/display_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>
#include <utility>

namespace thermnet::importer::spice {

namespace {

using Key = std::pair<std::string, std::string>;

Key key_of(const std::string& a, const std::string& b) {
  return a < b ? Key{a, b} : Key{b, a};
}

struct Segment {
  std::vector<std::size_t> caps;
  std::vector<std::size_t> rs;
  bool visited = false;
};

/// What touches a node besides its segments.
struct Attachments {
  std::vector<std::size_t> r_ground; // resistors to ground
  std::vector<std::size_t> c_ground; // capacitors to ground
  std::size_t others = 0;            // anything else: other resistors, sources, .ic
  bool source = false;               // a current source
  std::vector<Key> segments;         // the segments at the node
};

std::string shown(const std::string& node) {
  return node == "0" ? "0 (ground)" : lang::excerpt_for_display(node);
}

class Finder {
public:
  Finder(const std::vector<Element>& e, const std::vector<bool>& usable,
         const std::function<bool(const std::string&)>& held, const std::set<std::string>& ic,
         Report& report)
      : e_(e), usable_(usable), held_(held), ic_(ic), report_(report) {}

  std::vector<FosterChain> run() {
    for (std::size_t i = 0; i < e_.size(); ++i)
      if (usable_[i] && e_[i].kind == 'c' && e_[i].a != "0" && e_[i].b != "0")
        seg_[key_of(e_[i].a, e_[i].b)].caps.push_back(i);
    if (seg_.empty()) return {};
    for (std::size_t i = 0; i < e_.size(); ++i) {
      if (!usable_[i]) continue;
      const Element& el = e_[i];
      if (el.kind == 'r') {
        if (auto s = seg_.find(key_of(el.a, el.b)); s != seg_.end()) {
          s->second.rs.push_back(i);
          continue;
        }
      }
      if (el.kind == 'c' && el.a != "0" && el.b != "0") continue;
      for (const std::string* n : {&el.a, &el.b}) {
        if (*n == "0") continue;
        Attachments& at = att_[*n];
        const std::string& other = n == &el.a ? el.b : el.a;
        if (el.kind == 'r' && other == "0")
          at.r_ground.push_back(i);
        else if (el.kind == 'c' && other == "0")
          at.c_ground.push_back(i);
        else
          ++at.others;
        if (el.kind == 'i') at.source = true;
      }
    }
    for (const auto& n : ic_)
      ++att_[n].others;
    for (auto& [k, s] : seg_) {
      att_[k.first].segments.push_back(k);
      att_[k.second].segments.push_back(k);
    }
    std::vector<FosterChain> chains;
    for (auto& [k, s] : seg_) {
      if (s.visited) continue;
      try {
        if (auto c = chain(k)) chains.push_back(std::move(*c));
      } catch (const ImportError& err) {
        report_.error(err);
      }
    }
    return chains;
  }

private:
  bool inner(const std::string& n) {
    const Attachments& a = att_[n];
    return !held_(n) && a.segments.size() == 2 && a.others == 0 && a.r_ground.empty() &&
           a.c_ground.empty();
  }

  /// An end whose only other attachments are resistors and capacitors to ground.
  bool extendable(const std::string& n) {
    const Attachments& a = att_[n];
    return !held_(n) && a.segments.size() == 1 && a.others == 0 && !a.r_ground.empty() &&
           !a.c_ground.empty();
  }

  std::optional<FosterChain> chain(const Key& start) {
    // Walk from the segment both ways through inner nodes.
    std::vector<std::string> nodes{start.first, start.second};
    std::vector<Key> segs{start};
    seg_[start].visited = true;
    for (int side = 0; side < 2; ++side) {
      for (;;) {
        const std::string end = side == 0 ? nodes.front() : nodes.back();
        if (!inner(end)) break;
        const Key& last = side == 0 ? segs.front() : segs.back();
        const auto& at = att_[end].segments;
        const Key next = at[0] == last ? at[1] : at[0];
        if (seg_[next].visited)
          throw ImportError(e_[seg_[start].caps.front()].at, "foster-chain",
                            "these capacitors between nodes form a closed loop of R || C cells, "
                            "not a Foster chain: it has no ends to convert between");
        seg_[next].visited = true;
        const std::string far = next.first == end ? next.second : next.first;
        if (side == 0) {
          nodes.insert(nodes.begin(), far);
          segs.insert(segs.begin(), next);
        } else {
          nodes.push_back(far);
          segs.push_back(next);
        }
      }
    }
    const std::size_t first_cap = seg_[start].caps.front();
    for (const Key& k : segs)
      if (seg_[k].rs.empty()) {
        const Element& c = e_[seg_[k].caps.front()];
        throw ImportError(c.at, "foster-chain",
                          fmt::format("capacitor '{}' between nodes {} and {} has no resistor "
                                      "across it, so it is no Foster cell; thermnet's capacities "
                                      "are to ground (write a capacitor to node 0)",
                                      lang::excerpt_for_display(c.name), shown(c.a), shown(c.b)));
      }
    FosterChain fc;
    std::size_t earliest = first_cap;
    for (const Key& k : segs)
      earliest = std::min(earliest, *std::min_element(seg_[k].caps.begin(), seg_[k].caps.end()));
    fc.at = e_[earliest].at;
    std::vector<FosterCell> cells;
    for (const Key& k : segs) {
      const Segment& s = seg_[k];
      FosterCell cell;
      double g = 0;
      for (std::size_t i : s.rs)
        g += 1 / e_[i].value;
      for (std::size_t i : s.caps)
        cell.C += e_[i].value;
      cell.R = 1 / g;
      cells.push_back(cell);
      fc.consumed.insert(fc.consumed.end(), s.rs.begin(), s.rs.end());
      fc.consumed.insert(fc.consumed.end(), s.caps.begin(), s.caps.end());
    }
    // Extend an end that holds only R || C to ground, when the other end is free.
    std::string& front = nodes.front();
    std::string& back = nodes.back();
    const bool ext_front = !held_(back) && extendable(front);
    const bool ext_back = !held_(front) && extendable(back);
    if (ext_front && ext_back)
      throw ImportError(fc.at, "foster-chain",
                        fmt::format("cannot tell which end of the Foster chain from {} to {} is "
                                    "driven: both hold only R || C to ground",
                                    shown(front), shown(back)));
    if (ext_front || ext_back) {
      const std::string end = ext_front ? front : back;
      const Attachments& a = att_[end];
      FosterCell cell;
      double g = 0;
      for (std::size_t i : a.r_ground)
        g += 1 / e_[i].value;
      for (std::size_t i : a.c_ground)
        cell.C += e_[i].value;
      cell.R = 1 / g;
      fc.consumed.insert(fc.consumed.end(), a.r_ground.begin(), a.r_ground.end());
      fc.consumed.insert(fc.consumed.end(), a.c_ground.begin(), a.c_ground.end());
      if (ext_front) {
        nodes.insert(nodes.begin(), "0");
        cells.insert(cells.begin(), cell);
      } else {
        nodes.push_back("0");
        cells.push_back(cell);
      }
    }
    const std::string& a = nodes.front();
    const std::string& b = nodes.back();
    const bool ha = held_(a), hb = held_(b);
    bool driven_front = true;
    if (ha && hb) {
      report_.note(fc.at, fmt::format("the Foster chain from {} to {} joins two held nodes and "
                                      "changes no temperature: not written",
                                      shown(a), shown(b)));
      fc.written = false;
      fc.driven = a;
      fc.far = b;
      return fc;
    }
    if (ha || hb) {
      driven_front = hb;
    } else {
      const bool sa = att_[a].source, sb = att_[b].source;
      if (sa == sb)
        throw ImportError(fc.at, "foster-chain",
                          fmt::format("cannot tell which end of the Foster chain from {} to {} is "
                                      "driven: hold one end (a V source or node 0) or heat one "
                                      "(an I source)",
                                      shown(a), shown(b)));
      driven_front = sa;
    }
    if (!driven_front) {
      std::reverse(nodes.begin(), nodes.end());
      std::reverse(cells.begin(), cells.end());
    }
    fc.driven = nodes.front();
    fc.far = nodes.back();
    fc.far_held = held_(fc.far);
    fc.inner.assign(nodes.begin() + 1, nodes.end() - 1);
    fc.cells = std::move(cells);
    return fc;
  }

  const std::vector<Element>& e_;
  const std::vector<bool>& usable_;
  const std::function<bool(const std::string&)>& held_;
  const std::set<std::string>& ic_;
  Report& report_;
  std::map<Key, Segment> seg_;
  std::map<std::string, Attachments> att_;
};

} // namespace

std::vector<FosterChain> find_foster_chains(const std::vector<Element>& elements,
                                            const std::vector<bool>& usable,
                                            const std::function<bool(const std::string&)>& held,
                                            const std::set<std::string>& with_ic, Report& report) {
  return Finder(elements, usable, held, with_ic, report).run();
}

} // namespace thermnet::importer::spice
