#pragma once
// Brute-force oracles for swept volumes: exact distance to one tool position, and the union of
// densely sampled positions along a move.

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/move.hpp"

namespace cwe::test {

// A straight move from tip a to tip b, the axis turning from axis_a to axis_b (any lengths).
inline Move line(const Vec3& a, const Vec3& b, const Vec3& axis_a, const Vec3& axis_b) {
  Move m;
  m.start = a;
  m.end = b;
  m.start_axis = axis_a.normalized();
  m.end_axis = axis_b.normalized();
  return m;
}

// Exact signed distance from a TCS point to the cutter's surface (negative inside): distance in
// the meridian plane to the profile outline or the top disc.
inline double signed_distance(const Cutter& cutter, const Vec3& local) {
  const Vec2 q(std::hypot(local.x(), local.y()), local.z());
  const Profile& profile = cutter.profile();
  double d = profile.closest(q).distance;
  const double h = profile.height();
  const Vec2 top(std::clamp(q.x(), 0.0, profile.top_radius()), h);
  d = std::min(d, (q - top).norm());
  return profile.contains(q.x(), q.y()) ? -d : d;
}

// Distance sign of p against the union of the tool at `samples` positions of the move.
inline double union_signed_distance(const Cutter& cutter, const Move& move, const Vec3& p,
                                    int samples) {
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= samples; ++k) {
    const double u = static_cast<double>(k) / samples;
    const Frame f = Frame::from_z(move.position(u), move.axis(u), Vec3::UnitX());
    best = std::min(best, signed_distance(cutter, f.to_local(p)));
  }
  return best;
}

// Which side of the true swept volume (the union of the tool over every u in [0, 1]) p lies on:
// -1 when some tool position holds p deeper than `band`, +1 when every position is farther than
// `band` from it, 0 otherwise (p is within `band` of the boundary). Branch and bound on u: the
// distance to the tool changes by at most the farthest a tool point travels, which on [u0, u1]
// is at most (u1 - u0)·(path length + reach × axis turn), the move being parametrised at
// constant speed and turn rate; so an interval whose ends are both farther than band plus half
// its travel cannot come closer. `reach` bounds |tool point − tip|.
inline int union_side(const Cutter& cutter, const Move& move, const Vec3& p, double band,
                      double reach) {
  const double travel = move.length() + reach * move.axis_angle();
  const auto distance = [&](double u) {
    return signed_distance(
        cutter, Frame::from_z(move.position(u), move.axis(u), Vec3::UnitX()).to_local(p));
  };
  struct Span {
    double u0, u1, d0, d1;
  };
  std::vector<Span> todo{{0.0, 1.0, distance(0.0), distance(1.0)}};
  bool near = false;
  while (!todo.empty()) {
    const Span span = todo.back();
    todo.pop_back();
    if (span.d0 < -band || span.d1 < -band) return -1;
    const double reach_in_span = (span.u1 - span.u0) * travel;
    if (std::min(span.d0, span.d1) - reach_in_span / 2 > band) continue;
    if (reach_in_span < band) {  // cannot be resolved further: within the band, or a bit beyond
      near = true;
      continue;
    }
    const double um = 0.5 * (span.u0 + span.u1);
    const double dm = distance(um);
    todo.push_back({span.u0, um, span.d0, dm});
    todo.push_back({um, span.u1, dm, span.d1});
  }
  return near ? 0 : 1;
}

}  // namespace cwe::test
