#include "plot/geometry.hpp"

#include "plot/style.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <unordered_set>
#include <utility>

namespace thermnet::plot {
namespace {

// The drawable points of a series in pixels, one polyline per run between points that cannot be
// drawn.
std::vector<std::vector<Point>> every_point_segments(const Series& s, const Mapping& m,
                                                     std::size_t n) {
  std::vector<std::vector<Point>> segs;
  std::vector<Point> cur;
  for (std::size_t i = 0; i < n; ++i) {
    Point p{};
    if (!m.at(s.x[i], s.y[i], p)) {
      if (!cur.empty()) segs.push_back(std::move(cur));
      cur.clear();
      continue;
    }
    cur.push_back(p);
  }
  if (!cur.empty()) segs.push_back(std::move(cur));
  return segs;
}

// Per pixel column, the first, lowest, highest and last point of a series in data order, so
// peaks survive; a gap breaks the line only where it spans a column.
std::vector<std::vector<Point>> column_segments(const Series& s, const Mapping& m, std::size_t n) {
  std::vector<std::vector<Point>> segs;
  std::vector<Point> cur;
  auto end_segment = [&] {
    if (!cur.empty()) segs.push_back(std::move(cur));
    cur.clear();
  };
  struct Bucket {
    bool any = false;
    long long col = 0;
    std::size_t i_first = 0, i_min = 0, i_max = 0, i_last = 0;
    Point first{}, min{}, max{}, last{};
  } b;
  auto flush = [&] {
    if (!b.any) return;
    std::array<std::pair<std::size_t, Point>, 4> pts = {
        {{b.i_first, b.first}, {b.i_min, b.min}, {b.i_max, b.max}, {b.i_last, b.last}}};
    std::sort(pts.begin(), pts.end(),
              [](const auto& a, const auto& c) { return a.first < c.first; });
    for (std::size_t k = 0; k < pts.size(); ++k)
      if (k == 0 || pts[k].first != pts[k - 1].first) cur.push_back(pts[k].second);
    b.any = false;
  };
  bool gap = false;
  long long last_col = LLONG_MIN;
  for (std::size_t i = 0; i < n; ++i) {
    Point p{};
    if (!m.at(s.x[i], s.y[i], p)) {
      gap = true;
      continue;
    }
    const long long col = m.column(p.x);
    if (gap) {
      gap = false;
      if (col != last_col) {
        flush();
        end_segment();
      }
    }
    if (b.any && col != b.col) flush();
    if (!b.any) {
      b.any = true;
      b.col = col;
      b.i_first = b.i_min = b.i_max = i;
      b.first = b.min = b.max = p;
    } else if (p.y < b.min.y) {
      b.i_min = i;
      b.min = p;
    } else if (p.y > b.max.y) {
      b.i_max = i;
      b.max = p;
    }
    b.i_last = i;
    b.last = p;
    last_col = col;
  }
  flush();
  end_segment();
  return segs;
}

// Every stride-th point when there are more than `cap`: x not increasing (e.g. a parametric
// curve) defeats the columns, and this last resort keeps the output bounded.
void thin_out(std::vector<std::vector<Point>>& segs, std::size_t cap) {
  std::size_t total = 0;
  for (const auto& seg : segs)
    total += seg.size();
  if (total <= cap) return;
  const std::size_t stride = (total + cap - 1) / cap;
  std::vector<std::vector<Point>> thin;
  std::size_t k = 0;
  for (const auto& seg : segs) {
    std::vector<Point> t;
    for (const Point& p : seg)
      if (k++ % stride == 0) t.push_back(p);
    if (!t.empty()) thin.push_back(std::move(t));
  }
  segs = std::move(thin);
}

// Series data as pixel polylines. Small series keep every point; large ones (more than two points
// per pixel column) keep, per column, the first, lowest, highest and last point, so peaks survive
// and the size is bounded; gaps narrower than a column are then ignored.
std::vector<std::vector<Point>> raw_segments(const Series& s, const Mapping& m) {
  const std::size_t n = std::min(s.x.size(), s.y.size());
  const double columns = std::max(1.0, std::ceil(m.plot.w));
  if (!(static_cast<double>(n) > 2 * columns + 16)) return every_point_segments(s, m, n);
  std::vector<std::vector<Point>> segs = column_segments(s, m, n);
  thin_out(segs, static_cast<std::size_t>(8 * columns + 64));
  return segs;
}

// Drops points closer than tol px to the polyline through the kept ones (Douglas-Peucker).
std::vector<Point> simplify(const std::vector<Point>& pts, double tol) {
  const std::size_t n = pts.size();
  if (n < 3) return pts;
  std::vector<char> keep(n, 0);
  keep[0] = keep[n - 1] = 1;
  std::vector<std::pair<std::size_t, std::size_t>> todo{{0, n - 1}};
  while (!todo.empty()) {
    const auto [a, b] = todo.back();
    todo.pop_back();
    if (b <= a + 1) continue;
    const double dx = pts[b].x - pts[a].x, dy = pts[b].y - pts[a].y;
    const double len2 = dx * dx + dy * dy;
    double worst = -1;
    std::size_t at = a;
    for (std::size_t i = a + 1; i < b; ++i) {
      // Distance to the segment (not the line), so that back-and-forth spikes are kept.
      double t = len2 > 0 ? ((pts[i].x - pts[a].x) * dx + (pts[i].y - pts[a].y) * dy) / len2 : 0;
      t = std::clamp(t, 0.0, 1.0);
      const double ex = pts[a].x + t * dx - pts[i].x, ey = pts[a].y + t * dy - pts[i].y;
      const double d2 = ex * ex + ey * ey;
      if (d2 > worst) {
        worst = d2;
        at = i;
      }
    }
    if (worst > tol * tol) {
      keep[at] = 1;
      todo.push_back({a, at});
      todo.push_back({at, b});
    }
  }
  std::vector<Point> out;
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i]) out.push_back(pts[i]);
  return out;
}

} // namespace

std::vector<std::vector<Point>> line_segments(const Series& s, const Mapping& m) {
  std::vector<std::vector<Point>> segs = raw_segments(s, m);
  for (auto& seg : segs)
    seg = simplify(seg, 0.2);
  return segs;
}

std::vector<Point> marker_points(const Series& s, const Mapping& m) {
  const std::size_t n = std::min(s.x.size(), s.y.size());
  const double margin = kMarkerRadius + 2;
  const bool dense = static_cast<double>(n) > 2 * std::max(1.0, m.plot.w);
  std::unordered_set<long long> used;
  std::vector<Point> pts;
  const double cell = 2 * kMarkerRadius;
  for (std::size_t i = 0; i < n; ++i) {
    Point p{};
    if (!m.at(s.x[i], s.y[i], p)) continue;
    if (p.x < m.plot.x - margin || p.x > m.plot.right() + margin || p.y < m.plot.y - margin ||
        p.y > m.plot.bottom() + margin)
      continue;
    if (dense) {
      const auto cx = static_cast<long long>(std::floor((p.x - m.plot.x + margin) / cell));
      const auto cy = static_cast<long long>(std::floor((p.y - m.plot.y + margin) / cell));
      if (!used.insert(cx * 1000003LL + cy).second) continue;
    }
    pts.push_back(p);
  }
  return pts;
}

std::vector<std::vector<Point>> band_polygons(const Band& b, const Mapping& m) {
  const std::size_t n = std::min({b.x.size(), b.lo.size(), b.hi.size()});
  const double columns = std::max(1.0, std::ceil(m.plot.w));
  const bool decimate = static_cast<double>(n) > 2 * columns + 16;
  std::vector<std::vector<Point>> polys;
  std::vector<Point> upper, lower;
  auto end_run = [&] {
    if (!upper.empty()) {
      std::vector<Point> poly = upper;
      poly.insert(poly.end(), lower.rbegin(), lower.rend());
      polys.push_back(std::move(poly));
    }
    upper.clear();
    lower.clear();
  };
  bool gap = false;
  long long col_cur = LLONG_MIN;
  for (std::size_t i = 0; i < n; ++i) {
    Point ph{}, pl{};
    if (!m.at(b.x[i], b.hi[i], ph) || !m.at(b.x[i], b.lo[i], pl)) {
      gap = true;
      continue;
    }
    if (ph.y > pl.y) std::swap(ph.y, pl.y); // upper edge: smaller pixel y
    if (decimate) {
      const long long col = m.column(ph.x);
      if (gap && col != col_cur) end_run();
      gap = false;
      if (!upper.empty() && col == col_cur) {
        upper.back().y = std::min(upper.back().y, ph.y);
        lower.back().y = std::max(lower.back().y, pl.y);
        continue;
      }
      col_cur = col;
    } else if (gap) {
      end_run();
      gap = false;
    }
    upper.push_back(ph);
    lower.push_back(pl);
  }
  end_run();
  return polys;
}

} // namespace thermnet::plot
