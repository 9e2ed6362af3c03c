#include "kernel/core/network.hpp"
#include "kernel/core/sorted_runs.hpp"

#include "lang/model.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace thermnet {
namespace {

/// First pass: records which (row, col) pairs of unknowns elements touch.
class RecordingLayout final : public JacobianLayout {
public:
  RecordingLayout(std::vector<std::pair<int, int>>& pairs, const std::vector<int>& unknown_of)
      : pairs_(pairs), unknown_of_(unknown_of) {}
  int slot(int row, int col) override {
    const int r = unknown_of_[static_cast<std::size_t>(row)];
    const int c = unknown_of_[static_cast<std::size_t>(col)];
    if (r >= 0 && c >= 0) pairs_.emplace_back(r, c);
    return 0;
  }

private:
  std::vector<std::pair<int, int>>& pairs_;
  const std::vector<int>& unknown_of_;
};

/// Second pass: hands out CSR positions; pairs touching a boundary get the scratch slot.
class SlotLayout final : public JacobianLayout {
public:
  SlotLayout(const SparsityPattern& p, const std::vector<int>& unknown_of)
      : p_(p), unknown_of_(unknown_of) {}
  int slot(int row, int col) override {
    int r = unknown_of_[static_cast<std::size_t>(row)];
    int c = unknown_of_[static_cast<std::size_t>(col)];
    if (r < 0 || c < 0) return p_.nnz(); // scratch: boundaries are not unknowns
    auto begin = p_.col_idx.begin() + p_.row_ptr[static_cast<std::size_t>(r)];
    auto end = p_.col_idx.begin() + p_.row_ptr[static_cast<std::size_t>(r) + 1];
    return static_cast<int>(std::lower_bound(begin, end, c) - p_.col_idx.begin());
  }

private:
  const SparsityPattern& p_;
  const std::vector<int>& unknown_of_;
};

/// The plugins of the kinds a network names: big networks name the same kind many times in a row,
/// so the last one found is kept.
class KindLookup {
public:
  explicit KindLookup(const ElementRegistry& registry) : registry_(registry) {}
  const ElementPlugin* find(std::string_view kind) {
    if (!last_ || kind != last_kind_) {
      last_ = registry_.find(kind);
      last_kind_ = kind;
    }
    return last_;
  }

private:
  const ElementRegistry& registry_;
  std::string last_kind_;
  const ElementPlugin* last_ = nullptr;
};

std::unique_ptr<Element> build(const lang::ElementSpec& e, KindLookup& kinds) {
  if (e.composite() == lang::Composite::series) {
    double R = 0.0;
    for (const auto& part : e.parts())
      R += 1.0 / part.schema->conductance(part.key_values());
    return std::make_unique<LinearLink>(e.nodes()[0], e.nodes()[1], 1.0 / R);
  }
  const ElementPlugin* plugin = kinds.find(e.kind());
  if (!plugin) throw NetworkError(fmt::format("no plugin provides element kind '{}'", e.kind()));
  return plugin->create(e);
}

/// The CSR pattern of `n` rows holding the (row, col) pairs: the pairs are bucketed by row, and
/// only each row's few columns are sorted (a sort of all pairs costs more at 100,000 unknowns).
SparsityPattern pattern_of(int n, const std::vector<std::pair<int, int>>& pairs) {
  const auto rows = static_cast<std::size_t>(n);
  std::vector<int> start(rows + 1, 0);
  for (const auto& pair : pairs)
    ++start[static_cast<std::size_t>(pair.first) + 1];
  for (std::size_t r = 0; r < rows; ++r)
    start[r + 1] += start[r];
  std::vector<int> cols(pairs.size());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const auto& [r, c] : pairs)
    cols[static_cast<std::size_t>(fill[static_cast<std::size_t>(r)]++)] = c;
  SparsityPattern p;
  p.n = n;
  p.row_ptr.assign(rows + 1, 0);
  p.col_idx.reserve(pairs.size());
  for (std::size_t r = 0; r < rows; ++r) {
    const auto begin = cols.begin() + start[r], end = cols.begin() + start[r + 1];
    std::sort(begin, end);
    p.col_idx.insert(p.col_idx.end(), begin, std::unique(begin, end));
    p.row_ptr[r + 1] = static_cast<int>(p.col_idx.size());
  }
  return p;
}

/// Elements ahead of the one being stamped whose memory is requested early: element objects are
/// scattered over the heap, and large networks would otherwise wait for memory at every one.
constexpr std::size_t kPrefetchDistance = 8;

} // namespace

Network::Network(lang::NetworkSpec spec, const ElementRegistry& registry) : spec_(std::move(spec)) {
  const std::size_t n = spec_.nodes.size();
  unknown_of_.assign(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (spec_.nodes[i].boundary) {
      boundary_nodes_.push_back(static_cast<int>(i));
      continue;
    }
    unknown_of_[i] = static_cast<int>(unknown_nodes_.size());
    unknown_nodes_.push_back(static_cast<int>(i));
    capacities_.push_back(spec_.nodes[i].C);
  }
  KindLookup kinds(registry);
  pieces_.reserve(spec_.elements.size()); // one per element but a parallel block's parts
  const auto add = [&](const lang::ElementSpec& e, int spec_element) {
    std::unique_ptr<Element> element = build(e, kinds);
    Piece piece{spec_element};
    if (const auto* link = dynamic_cast<const LinearLink*>(element.get())) {
      piece.batch = static_cast<int>(links_.size());
      links_.add(link->a(), link->b(), link->conductance());
    } else {
      piece.element = static_cast<int>(elements_.size());
      if (e.schema && e.schema->observes) sensors_.emplace_back(spec_element, piece.element);
      elements_.push_back(std::move(element));
    }
    pieces_.push_back(piece);
  };
  for (std::size_t k = 0; k < spec_.elements.size(); ++k) {
    const auto& e = spec_.elements[k];
    if (e.composite() == lang::Composite::parallel)
      for (const auto& part : e.parts())
        add(part, static_cast<int>(k));
    else
      add(e, static_cast<int>(k));
  }
  // Internal states of elements follow the nodes in the node arrays and the temperatures among
  // the unknowns.
  for (const Piece& p : pieces_) {
    if (p.element < 0) continue;
    Element& e = *elements_[static_cast<std::size_t>(p.element)];
    const int count = e.state_count();
    if (count > 0) e.assign_states(static_cast<int>(n) + state_count_);
    for (int j = 0; j < count; ++j) {
      unknown_of_.push_back(static_cast<int>(unknown_nodes_.size()) + state_count_++);
      capacities_.push_back(1.0);
      state_owner_.push_back(p.element);
      state_names_.push_back(spec_.elements[static_cast<std::size_t>(p.spec_element)].name + "." +
                             e.state_name(j));
    }
  }
  // Fix the pattern: every unknown's diagonal plus what the elements declare (the pairs are freed
  // before the Jacobian arrays below are allocated, which then take their place in the heap).
  pattern_ = [&] {
    std::vector<std::pair<int, int>> pairs;
    RecordingLayout recorder(pairs, unknown_of_);
    links_.declare(recorder);
    for (auto& e : elements_)
      e->declare(recorder);
    for (int u = 0; u < size(); ++u)
      pairs.emplace_back(u, u);
    return pattern_of(size(), pairs);
  }();
  SlotLayout slots(pattern_, unknown_of_);
  links_.declare(slots);
  for (auto& e : elements_) {
    e->declare(slots);
    event_offset_.push_back(event_count_);
    event_count_ += e->event_count();
  }
  const std::size_t entries = n + static_cast<std::size_t>(state_count_);
  T_all_.assign(entries, 0.0);
  F_all_.assign(entries, 0.0);
  F_piece_.assign(entries, 0.0);
  J_links_.assign(static_cast<std::size_t>(pattern_.nnz()) + 1, 0.0);
  links_.stamp_jacobian(J_links_.data());
  J_all_ = J_links_;
}

void Network::expand(double t, const double* T, double* all) const {
  for (std::size_t u = 0; u < unknown_nodes_.size(); ++u)
    all[unknown_nodes_[u]] = T[u];
  for (int b : boundary_nodes_)
    all[b] = spec_.nodes[static_cast<std::size_t>(b)].T.at(t);
}

double Network::sensor_reading(std::size_t e, double t, const double* T) {
  for (const auto& [spec_element, element] : sensors_)
    if (static_cast<std::size_t>(spec_element) == e) {
      load(t, T);
      if (auto r = elements_[static_cast<std::size_t>(element)]->sensor_reading(T_all_.data()))
        return *r;
    }
  throw std::invalid_argument(
      fmt::format("element '{}' is not a sensor", spec_.elements.at(e).name));
}

std::vector<int> Network::sensor_elements() const {
  std::vector<int> out;
  for (const auto& [spec_element, element] : sensors_)
    out.push_back(spec_element);
  return out;
}

void Network::load(double t, const double* T) {
  expand(t, T, T_all_.data());
  std::copy(T + unknown_nodes_.size(), T + size(), T_all_.begin() + spec_.nodes.size());
}

void Network::stamp_all(double t, const double* T, bool with_jacobian) {
  load(t, T);
  std::fill(F_all_.begin(), F_all_.end(), 0.0);
  // Right-hand sides outnumber Jacobians by ~50 to 1: skip the derivatives when not asked for.
  double* J = nullptr;
  if (with_jacobian) {
    std::copy(J_links_.begin(), J_links_.end(), J_all_.begin());
    J = J_all_.data();
  }
  links_.stamp_flows(T_all_.data(), F_all_.data());
  const std::size_t count = elements_.size();
  for (std::size_t k = 0; k < count; ++k) {
    if (k + kPrefetchDistance < count) __builtin_prefetch(elements_[k + kPrefetchDistance].get());
    elements_[k]->stamp(t, T_all_.data(), F_all_.data(), J);
  }
}

void Network::heat_balance(double t, const double* T, double* F) {
  if (!inputs_.empty()) inputs_.at(spec_, t);
  stamp_all(t, T, false);
  for (std::size_t u = 0; u < unknown_nodes_.size(); ++u)
    F[u] = F_all_[static_cast<std::size_t>(unknown_nodes_[u])];
  std::copy(F_all_.begin() + static_cast<std::ptrdiff_t>(spec_.nodes.size()), F_all_.end(),
            F + unknown_nodes_.size());
}

void Network::jacobian(double t, const double* T, double* values) {
  stamp_all(t, T, true);
  std::copy(J_all_.begin(), J_all_.end() - 1, values);
}

void Network::events(double t, const double* T, double* g) {
  load(t, T);
  for (std::size_t k = 0; k < elements_.size(); ++k)
    if (elements_[k]->event_count() > 0)
      elements_[k]->events(t, T_all_.data(), g + event_offset_[k]);
}

bool Network::apply_events(double t, const double* T, const std::vector<int>& fired) {
  load(t, T);
  bool changed = false;
  for (std::size_t k = 0; k < elements_.size(); ++k)
    for (int j = 0; j < elements_[k]->event_count(); ++j)
      if (fired[static_cast<std::size_t>(event_offset_[k] + j)])
        changed |= elements_[k]->apply_event(j, t, T_all_.data());
  return changed;
}

std::string Network::event_name(int k) const {
  for (const Piece& p : pieces_) {
    if (p.element < 0) continue;
    const auto owner = static_cast<std::size_t>(p.element);
    const int first = event_offset_[owner];
    if (k < first || k >= first + elements_[owner]->event_count()) continue;
    const lang::ElementSpec& e = spec_.elements[static_cast<std::size_t>(p.spec_element)];
    return fmt::format("{} '{}'", e.kind(), e.name);
  }
  return ThermalSystem::event_name(k);
}

void Network::init_events(double t, const double* T) {
  load(t, T);
  for (auto& e : elements_)
    e->init_events(t, T_all_.data());
}

std::vector<double> Network::breakpoints(double t0, double t1) const {
  // Each input's corners are increasing, and the tables of one data file share them: the runs are
  // merged (a run equal to what is already there adds nothing), not the whole sorted again.
  std::vector<double> out, run;
  const auto merge = [&](std::vector<double>& r) {
    if (!std::is_sorted(r.begin(), r.end())) std::sort(r.begin(), r.end());
    const auto lo = std::upper_bound(r.begin(), r.end(), t0);
    merge_sorted_run(out, lo, std::upper_bound(lo, r.end(), t1));
  };
  for (const auto& e : elements_) {
    run.clear();
    e->breakpoints(run);
    merge(run);
  }
  for (const auto& node : spec_.nodes)
    if (node.boundary) {
      run.assign(node.T.corners().begin(), node.T.corners().end());
      merge(run);
    }
  return out;
}

void Network::explain_failure(double t, double t0, double t1, bool out_of_steps) const {
  if (!inputs_.empty()) inputs_.unbounded_near(spec_, t, t0);
  if (!out_of_steps) return;
  // The input that made the integrator restart most often, when its restarts took the steps.
  const lang::Signal* most = nullptr;
  std::size_t corners = 0;
  std::string what;
  lang::Span where;
  const auto consider = [&](const lang::Signal& s, const auto& name, lang::Span statement) {
    const auto& c = s.corners();
    const auto n = static_cast<std::size_t>(std::upper_bound(c.begin(), c.end(), t1) -
                                            std::upper_bound(c.begin(), c.end(), t0));
    if (n <= corners) return;
    most = &s;
    corners = n;
    what = name();
    where = statement;
  };
  for (const auto& node : spec_.nodes)
    if (node.boundary)
      consider(
          node.T, [&] { return fmt::format("T of boundary '{}'", node.name); }, node.where);
  for (const auto& e : spec_.elements)
    for (const auto& [key, value] : e.values)
      consider(
          value, [&] { return fmt::format("{} of {} '{}'", key, e.kind(), e.name); }, e.where);
  if (!most || corners < 1000) return; // not what took the steps
  const lang::Signal::Shape* shape = most->shape_if();
  const bool located = shape && shape->mark.end > shape->mark.begin;
  const lang::Span mark = located ? shape->mark : where;
  const lang::Span at = located ? shape->at : lang::Span{where.file, where.begin, where.begin};
  throw lang::ModelError(lang::DiagnosticEngine::make(
      lang::DiagId::input_corners, at, mark, what, corners, "internal", fmt::format("{:.10g}", t)));
}

std::string Network::unknown_name(int i) const {
  const auto u = static_cast<std::size_t>(i);
  if (u < unknown_nodes_.size())
    return spec_.nodes.at(static_cast<std::size_t>(unknown_nodes_[u])).name;
  return state_names_.at(u - unknown_nodes_.size());
}

std::vector<double> Network::initial_state() const {
  std::vector<double> T0;
  T0.reserve(static_cast<std::size_t>(size()));
  for (int i : unknown_nodes_)
    T0.push_back(spec_.nodes[static_cast<std::size_t>(i)].T0.value_or(spec_.default_initial()));
  start_states(T0);
  return T0;
}

void Network::start_states(std::vector<double>& x) const {
  x.resize(static_cast<std::size_t>(size()), 0.0);
  if (state_count_ == 0) return;
  std::vector<double> all(spec_.nodes.size());
  expand(0.0, x.data(), all.data());
  for (std::size_t s = 0; s < state_owner_.size();) {
    const Element& e = *elements_[static_cast<std::size_t>(state_owner_[s])];
    e.initial_states(all.data(), x.data() + unknown_nodes_.size() + s);
    s += static_cast<std::size_t>(e.state_count());
  }
}

double Network::source_power(double t, const double* T) {
  load(t, T);
  double P = 0.0;
  for (const auto& e : elements_)
    P += e->power_in(t, T_all_.data());
  return P;
}

double Network::boundary_loss(double t, const double* T) {
  stamp_all(t, T, false);
  double loss = 0.0;
  for (std::size_t i = 0; i < spec_.nodes.size(); ++i)
    if (unknown_of_[i] < 0) loss += F_all_[i];
  return loss;
}

std::vector<char> Network::switching_elements() const {
  std::vector<char> out(spec_.elements.size(), 0);
  for (const Piece& p : pieces_)
    if (p.element >= 0 && elements_[static_cast<std::size_t>(p.element)]->event_count() > 0)
      out[static_cast<std::size_t>(p.spec_element)] = 1;
  return out;
}

void Network::element_heat(double t, const double* T, std::vector<std::vector<double>>& heat) {
  load(t, T);
  heat.resize(spec_.elements.size());
  for (std::size_t e = 0; e < heat.size(); ++e)
    heat[e].assign(spec_.elements[e].nodes().size(), 0.0);
  // Adds what the piece put into F_piece_ at the element's terminals, and clears F_piece_.
  const auto collect = [&](const Piece& p) {
    const auto terminals = spec_.elements[static_cast<std::size_t>(p.spec_element)].nodes();
    auto& h = heat[static_cast<std::size_t>(p.spec_element)];
    for (std::size_t j = 0; j < terminals.size(); ++j)
      h[j] += F_piece_[static_cast<std::size_t>(terminals[j])];
    for (int node : terminals)
      F_piece_[static_cast<std::size_t>(node)] = 0.0;
  };
  for (const Piece& p : pieces_) {
    if (p.batch >= 0) {
      const auto k = static_cast<std::size_t>(p.batch);
      const double q = links_.flow(k, T_all_.data());
      const auto [a, b] = links_.nodes(k);
      F_piece_[static_cast<std::size_t>(a)] -= q;
      F_piece_[static_cast<std::size_t>(b)] += q;
    } else {
      elements_[static_cast<std::size_t>(p.element)]->stamp(t, T_all_.data(), F_piece_.data(),
                                                            nullptr);
    }
    collect(p);
  }
  // Rates of internal states are not heat: cleared for the next use.
  std::fill(F_piece_.begin() + static_cast<std::ptrdiff_t>(spec_.nodes.size()), F_piece_.end(),
            0.0);
}

bool Network::affine() const {
  if (event_count_ > 0) return false;
  return std::all_of(elements_.begin(), elements_.end(),
                     [](const std::unique_ptr<Element>& e) { return e->affine(); });
}

bool Network::piecewise_linear() const {
  return affine() && piecewise_affine();
}

bool Network::piecewise_affine() const {
  if (event_count_ > 0) return false;
  for (const auto& e : elements_)
    if (!e->jacobian_piecewise_constant() || !e->piecewise_linear_inputs()) return false;
  for (const auto& node : spec_.nodes)
    if (node.boundary && !node.T.piecewise_linear()) return false;
  return std::all_of(capacities_.begin(), capacities_.end(), [](double c) { return c > 0.0; });
}

} // namespace thermnet
