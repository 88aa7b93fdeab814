#pragma once
// Brute-force oracles for swept volumes: exact distance to one tool position, and the union of
// densely sampled positions along a move.

#include <algorithm>
#include <cmath>
#include <limits>

#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/move.hpp"

namespace cwe::test {

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

}  // namespace cwe::test
