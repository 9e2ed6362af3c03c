// NetworkDerivatives: what a parameter moves in a network (capacities, initial state, boundary
// temperatures, element keys), found by comparing the network with its build at the moved value,
// and dF/dp evaluated piece by piece.

#include "kernel/core/network_derivatives.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

namespace thermnet {

namespace {

using lang::Signal;

/// True when two signals have the same shape and values.
bool same_signal(const Signal& a, const Signal& b) {
  if (a.kind() != b.kind()) return false;
  switch (a.kind()) {
  case Signal::Kind::constant:
    return a.constant == b.constant;
  case Signal::Kind::step:
  case Signal::Kind::pwl:
    return a.times() == b.times() && a.values() == b.values();
  case Signal::Kind::expression: {
    const Signal::Shape *sa = a.shape_if(), *sb = b.shape_if();
    return sa->program == sb->program && sa->scale == sb->scale && sa->offset == sb->offset;
  }
  }
  return false;
}

/// (b - a) / h as a signal of the same shape, when the two differ only in values (a constant, the
/// corner values of a step or pwl with the same corners, the scale and offset of one expression).
std::optional<Signal> signal_rate(const Signal& a, const Signal& b, double h) {
  if (a.kind() != b.kind()) return std::nullopt;
  switch (a.kind()) {
  case Signal::Kind::constant:
    return Signal::of((b.constant - a.constant) / h);
  case Signal::Kind::step:
  case Signal::Kind::pwl: {
    if (a.times() != b.times()) return std::nullopt;
    Signal r;
    Signal::Shape& s = r.shape(a.kind());
    s.t = a.times();
    s.v.resize(a.values().size());
    for (std::size_t k = 0; k < s.v.size(); ++k)
      s.v[k] = (b.values()[k] - a.values()[k]) / h;
    return r;
  }
  case Signal::Kind::expression: {
    const Signal::Shape *sa = a.shape_if(), *sb = b.shape_if();
    if (sa->program != sb->program) return std::nullopt;
    Signal r;
    Signal::Shape& s = r.shape(Signal::Kind::expression);
    s.program = sa->program;
    s.scale = (sb->scale - sa->scale) / h;
    s.offset = (sb->offset - sa->offset) / h;
    return r;
  }
  }
  return std::nullopt;
}

/// Same kind, terminals, node-valued keys and parts (the values of the keys may differ).
bool same_structure(const lang::ElementSpec& a, const lang::ElementSpec& b) {
  if (a.kind() != b.kind() || a.composite() != b.composite()) return false;
  if (!std::equal(a.nodes().begin(), a.nodes().end(), b.nodes().begin(), b.nodes().end()))
    return false;
  if (a.values.size() != b.values.size()) return false;
  for (auto ia = a.values.begin(), ib = b.values.begin(); ia != a.values.end(); ++ia, ++ib)
    if (ia->first != ib->first) return false;
  const auto pa = a.parts(), pb = b.parts();
  if (pa.size() != pb.size()) return false;
  for (std::size_t k = 0; k < pa.size(); ++k)
    if (!same_structure(pa[k], pb[k])) return false;
  for (const auto& key : a.schema ? a.schema->keys : std::vector<lang::KeySchema>{})
    if (key.type == lang::KeyType::node && a.node_key(key.name) != b.node_key(key.name))
      return false;
  return true;
}

/// True when the key values (and those of the parts) are the same.
bool same_values(const lang::ElementSpec& a, const lang::ElementSpec& b) {
  for (auto ia = a.values.begin(), ib = b.values.begin(); ia != a.values.end(); ++ia, ++ib)
    if (!same_signal(ia->second, ib->second)) return false;
  const auto pa = a.parts(), pb = b.parts();
  for (std::size_t k = 0; k < pa.size(); ++k)
    if (!same_values(pa[k], pb[k])) return false;
  return true;
}

/// The spec element (or parallel part) each piece of a network was built from, in the order the
/// Network builds its pieces.
std::vector<const lang::ElementSpec*> piece_specs(const lang::NetworkSpec& spec) {
  std::vector<const lang::ElementSpec*> out;
  for (const auto& e : spec.elements) {
    if (e.composite() == lang::Composite::parallel)
      for (const auto& part : e.parts())
        out.push_back(&part);
    else
      out.push_back(&e);
  }
  return out;
}

} // namespace

/// One parameter: the twin network and what moved in it.
struct NetworkDerivatives::Direction {
  std::unique_ptr<Network> twin;  // the network at the moved value
  double step = 1.0;              // p_j moved by this
  double scale = 1.0;             // typical size of p_j
  std::vector<double> dC;         // dC/dp per unknown (empty: none moved)
  std::vector<double> dT0;        // dT(0)/dp per unknown
  std::vector<int> boundaries;    // spec nodes of the boundaries that moved
  std::vector<char> boundary_set; // per spec node: a moved boundary
  /// A piece that moved, with its keys' rates when its kind differentiates itself.
  struct Piece {
    std::size_t index = 0;    // into the network's pieces
    bool differenced = false; // by the difference of its two builds
    lang::KeySignals rates;   // d key / dp of the keys that moved (key_derivative)
  };
  std::vector<Piece> pieces;
};

NetworkDerivatives::NetworkDerivatives(Network& net, std::vector<MovedSpec> moved,
                                       const ElementRegistry& registry)
    : net_(net), piece_specs_(piece_specs(net.spec())) {
  const std::size_t entries = net_.T_all_.size();
  F_.assign(entries, 0.0);
  A_.assign(entries, 0.0);
  B_.assign(entries, 0.0);
  check_network();
  for (auto& m : moved) {
    auto d = std::make_unique<Direction>();
    d->step = m.step;
    d->scale = m.scale;
    if (supported()) {
      try {
        d->twin = std::make_unique<Network>(std::move(m.spec), registry);
        prepare(*d);
      } catch (const std::exception& e) {
        why_not_ = fmt::format("the network at a moved parameter could not be built: {}", e.what());
      }
    }
    dirs_.push_back(std::move(d));
  }
}

NetworkDerivatives::~NetworkDerivatives() = default;

void NetworkDerivatives::check_network() {
  if (net_.event_count() > 0)
    why_not_ = "it switches by events (a thermostat)";
  else if (net_.state_count_ > 0)
    why_not_ = "an element has internal states";
  else if (net_.spec().settings.initial_steady)
    why_not_ = "the case starts from its steady state";
  else if (std::any_of(net_.capacities().begin(), net_.capacities().end(),
                       [](double c) { return !(c > 0.0); }))
    why_not_ = "it has arithmetic nodes (C = 0)";
}

void NetworkDerivatives::prepare(Direction& d) {
  const Network& a = net_;
  const Network& b = *d.twin;
  const lang::NetworkSpec &sa = a.spec(), &sb = b.spec();
  const auto changed_structure = [&] {
    if (!(d.step != 0.0) || !std::isfinite(d.step)) return true;
    if (sa.nodes.size() != sb.nodes.size() || sa.elements.size() != sb.elements.size() ||
        a.size() != b.size() || a.pieces_.size() != b.pieces_.size() || b.event_count() != 0 ||
        b.state_count_ != 0 || b.spec().settings.initial_steady)
      return true;
    for (std::size_t i = 0; i < sa.nodes.size(); ++i)
      if (sa.nodes[i].boundary != sb.nodes[i].boundary) return true;
    for (std::size_t k = 0; k < sa.elements.size(); ++k)
      if (!same_structure(sa.elements[k], sb.elements[k])) return true;
    for (std::size_t k = 0; k < a.pieces_.size(); ++k)
      if ((a.pieces_[k].batch < 0) != (b.pieces_[k].batch < 0)) return true;
    return false;
  };
  if (changed_structure()) {
    why_not_ = "a parameter changes the network's structure";
    return;
  }
  const double h = d.step;
  // Capacities and the initial state.
  const auto n = static_cast<std::size_t>(a.size());
  bool any = false;
  std::vector<double> dC(n);
  for (std::size_t u = 0; u < n; ++u) {
    dC[u] = (b.capacities()[u] - a.capacities()[u]) / h;
    any = any || dC[u] != 0.0;
  }
  if (any) d.dC = std::move(dC);
  const std::vector<double> T0a = a.initial_state(), T0b = b.initial_state();
  d.dT0.resize(n);
  for (std::size_t u = 0; u < n; ++u)
    d.dT0[u] = (T0b[u] - T0a[u]) / h;
  // Boundaries whose temperature moved.
  d.boundary_set.assign(sa.nodes.size(), 0);
  for (std::size_t i = 0; i < sa.nodes.size(); ++i)
    if (sa.nodes[i].boundary && !same_signal(sa.nodes[i].T, sb.nodes[i].T)) {
      d.boundaries.push_back(static_cast<int>(i));
      d.boundary_set[i] = 1;
    }
  // Pieces whose keys or terminal boundaries moved.
  const std::vector<const lang::ElementSpec*> twin_specs = piece_specs(sb);
  for (std::size_t k = 0; k < a.pieces_.size(); ++k) {
    const lang::ElementSpec& ea = *piece_specs_[k];
    const lang::ElementSpec& eb = *twin_specs[k];
    const bool keys = !same_values(ea, eb);
    const auto terminals = ea.nodes();
    const bool boundary = std::any_of(terminals.begin(), terminals.end(), [&](int node) {
      return d.boundary_set[static_cast<std::size_t>(node)] != 0;
    });
    // Elements whose conductance or flows depend on the boundaries they sense elsewhere (a
    // node-valued key) are differenced too when one moved.
    bool sensed = false;
    if (ea.schema)
      for (const auto& key : ea.schema->keys)
        if (key.type == lang::KeyType::node)
          if (auto node = ea.node_key(key.name);
              node && d.boundary_set[static_cast<std::size_t>(*node)] != 0)
            sensed = true;
    if (!keys && !boundary && !sensed) continue;
    Direction::Piece p;
    p.index = k;
    const auto& pa = a.pieces_[k];
    if (pa.batch >= 0) { // a linear link: through its conductance and terminal temperatures
      d.pieces.push_back(std::move(p));
      continue;
    }
    p.differenced = boundary || sensed || ea.composite() != lang::Composite::none || !ea.schema;
    if (!p.differenced)
      for (auto ia = ea.values.begin(), ib = eb.values.begin(); ia != ea.values.end(); ++ia, ++ib) {
        if (same_signal(ia->second, ib->second)) continue;
        const lang::KeySchema* key = ea.schema->key(ia->first);
        std::optional<Signal> rate = signal_rate(ia->second, ib->second, h);
        if (!key || !rate) {
          p.differenced = true;
          break;
        }
        p.rates.emplace(*key, std::move(*rate));
      }
    d.pieces.push_back(std::move(p));
  }
}

bool NetworkDerivatives::inert(int j) const {
  const Direction& d = *dirs_[static_cast<std::size_t>(j)];
  return d.pieces.empty() && d.dC.empty() && d.boundaries.empty() &&
         std::all_of(d.dT0.begin(), d.dT0.end(), [](double v) { return v == 0.0; });
}

std::size_t NetworkDerivatives::moved_pieces(int j) const {
  return dirs_[static_cast<std::size_t>(j)]->pieces.size();
}

std::size_t NetworkDerivatives::differenced_pieces(int j) const {
  const auto& pieces = dirs_[static_cast<std::size_t>(j)]->pieces;
  return static_cast<std::size_t>(
      std::count_if(pieces.begin(), pieces.end(), [](const auto& p) { return p.differenced; }));
}

double NetworkDerivatives::scale(int j) const {
  return dirs_[static_cast<std::size_t>(j)]->scale;
}

const std::vector<double>& NetworkDerivatives::capacities(int j) const {
  return dirs_[static_cast<std::size_t>(j)]->dC;
}

const std::vector<double>& NetworkDerivatives::initial_state(int j) const {
  return dirs_[static_cast<std::size_t>(j)]->dT0;
}

void NetworkDerivatives::boundary_derivative(int j, double t, double* all) const {
  const Direction& d = *dirs_[static_cast<std::size_t>(j)];
  for (std::size_t i = 0; i < net_.spec().nodes.size(); ++i)
    if (net_.spec().nodes[i].boundary) all[i] = 0.0;
  for (int b : d.boundaries) {
    const auto i = static_cast<std::size_t>(b);
    all[i] = (d.twin->spec().nodes[i].T.at(t) - net_.spec().nodes[i].T.at(t)) / d.step;
  }
}

void NetworkDerivatives::heat_balance(int j, double t, const double* T, double* dF) {
  Direction& d = *dirs_[static_cast<std::size_t>(j)];
  Network& b = *d.twin;
  const double h = d.step;
  net_.load(t, T);
  if (!d.boundaries.empty()) b.load(t, T);
  const double* Ta = net_.T_all_.data();
  const double* Tb = d.boundaries.empty() ? Ta : b.T_all_.data();
  std::fill(F_.begin(), F_.end(), 0.0);
  for (auto& p : d.pieces) {
    const Network::Piece& pa = net_.pieces_[p.index];
    if (pa.batch >= 0) {
      // G'(Ta' - Tb') - G (Ta - Tb) = (G' - G)(Ta - Tb) + G' ((Ta' - Ta) - (Tb' - Tb))
      const auto k = static_cast<std::size_t>(pa.batch);
      const auto kb = static_cast<std::size_t>(b.pieces_[p.index].batch);
      const auto [x, y] = net_.links_.nodes(k);
      const double G = net_.links_.conductance(k), Gb = b.links_.conductance(kb);
      const double dq =
          (Gb - G) / h * (Ta[x] - Ta[y]) + Gb * ((Tb[x] - Ta[x]) - (Tb[y] - Ta[y])) / h;
      F_[static_cast<std::size_t>(x)] -= dq;
      F_[static_cast<std::size_t>(y)] += dq;
      continue;
    }
    const Element& ea = *net_.elements_[static_cast<std::size_t>(pa.element)];
    if (!p.differenced) {
      if (ea.key_derivative(t, Ta, p.rates, F_.data())) continue;
      p.differenced = true; // the kind gives no derivative: difference it from now on
    }
    const Element& eb = *b.elements_[static_cast<std::size_t>(b.pieces_[p.index].element)];
    eb.stamp(t, Tb, A_.data(), nullptr);
    ea.stamp(t, Ta, B_.data(), nullptr);
    for (int node : piece_specs_[p.index]->nodes()) {
      const auto i = static_cast<std::size_t>(node);
      F_[i] += (A_[i] - B_[i]) / h;
      A_[i] = B_[i] = 0.0;
    }
  }
  const auto& unknowns = net_.unknown_nodes();
  for (std::size_t u = 0; u < unknowns.size(); ++u)
    dF[u] = F_[static_cast<std::size_t>(unknowns[u])];
}

} // namespace thermnet
