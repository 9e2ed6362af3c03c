#include "plot/svg_writer.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

namespace thermnet::plot {
namespace {

// A coordinate in tenths of a pixel (0 when not finite): how it is written, and how repeated
// points are recognised.
long long tenths(double v) {
  return std::isfinite(v) ? std::llround(std::clamp(v, -1e6, 1e6) * 10) : 0;
}

} // namespace

void SvgWriter::num(double v) {
  long long t = tenths(v);
  if (t < 0) {
    s += '-';
    t = -t;
  }
  fmt::format_to(std::back_inserter(s), "{}", t / 10);
  if (t % 10 != 0) {
    s += '.';
    s += static_cast<char>('0' + t % 10);
  }
}

std::string n1(double v) {
  SvgWriter o;
  o.num(v);
  return o.s;
}

void append_polylines(SvgWriter& o, const std::vector<std::vector<Point>>& segs) {
  for (const auto& seg : segs) {
    long long lx = LLONG_MIN, ly = LLONG_MIN;
    std::size_t emitted = 0;
    for (const Point& p : seg) {
      const long long tx = tenths(p.x), ty = tenths(p.y);
      if (tx == lx && ty == ly) continue;
      o.s += emitted == 0 ? "M" : emitted == 1 ? "L" : " ";
      o.num(p.x);
      o.s += ' ';
      o.num(p.y);
      lx = tx;
      ly = ty;
      ++emitted;
    }
  }
}

void append_polygons(SvgWriter& o, const std::vector<std::vector<Point>>& polys) {
  for (const auto& poly : polys) {
    append_polylines(o, {poly});
    o.s += 'Z';
  }
}

void append_marker(SvgWriter& o, Point p, int shape, double r) {
  switch (shape % 4) {
  case 0:
    o.s += 'M';
    o.num(p.x - r);
    o.s += ' ';
    o.num(p.y);
    o.f("a{0} {0} 0 1 0 {1} 0a{0} {0} 0 1 0 -{1} 0", n1(r), n1(2 * r));
    break;
  case 1: {
    const double h = r * 0.85;
    o.s += 'M';
    o.num(p.x - h);
    o.s += ' ';
    o.num(p.y - h);
    o.f("h{0}v{0}h-{0}z", n1(2 * h));
    break;
  }
  case 2:
    o.s += 'M';
    o.num(p.x);
    o.s += ' ';
    o.num(p.y - r * 1.15);
    o.f("l{0} {0} -{0} {0} -{0} -{0}z", n1(r * 1.15));
    break;
  default:
    o.s += 'M';
    o.num(p.x);
    o.s += ' ';
    o.num(p.y - r * 1.15);
    o.f("l{} {}h-{}z", n1(r * 1.1), n1(r * 1.9), n1(r * 2.2));
  }
}

} // namespace thermnet::plot
