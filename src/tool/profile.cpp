#include "cwe/tool/profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "cwe/core/assert.hpp"
#include "cwe/core/error.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {
namespace {

// Angle of `angle` brought into [reference, reference + 2π).
double wrap_from(double angle, double reference) {
  double a = std::fmod(angle - reference, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  return reference + a;
}

// Is the (unwrapped) angle `a` strictly inside the arc's sweep from start to end?
bool sweep_contains(double start, double end, double a) {
  const double lo = std::min(start, end);
  const double hi = std::max(start, end);
  const double w = wrap_from(a, lo);
  return w > lo && w < hi;
}

}  // namespace

ProfileSegment ProfileSegment::line(const Vec2& from, const Vec2& to) {
  ProfileSegment s;
  s.kind = Kind::kLine;
  s.start = from;
  s.end = to;
  return s;
}

ProfileSegment ProfileSegment::arc(const Vec2& from, const Vec2& to, const Vec2& center,
                                   bool counterclockwise) {
  ProfileSegment s;
  s.kind = Kind::kArc;
  s.start = from;
  s.end = to;
  s.center = center;
  s.radius = (from - center).norm();
  s.counterclockwise = counterclockwise;
  return s;
}

double ProfileSegment::start_angle() const {
  const Vec2 v = start - center;
  return std::atan2(v.y(), v.x());
}

double ProfileSegment::end_angle() const {
  const Vec2 v = end - center;
  const double a0 = start_angle();
  const double a1 = std::atan2(v.y(), v.x());
  if (counterclockwise) return wrap_from(a1, a0);  // a1 ∈ [a0, a0 + 2π)
  return a0 - (wrap_from(a0, a1) - a1);            // a1 ∈ (a0 - 2π, a0]
}

double ProfileSegment::length() const {
  if (kind == Kind::kLine) return (end - start).norm();
  return radius * std::abs(end_angle() - start_angle());
}

Vec2 ProfileSegment::point_at(double u) const {
  if (kind == Kind::kLine) return start + u * (end - start);
  const double a = start_angle() + u * (end_angle() - start_angle());
  return center + radius * Vec2(std::cos(a), std::sin(a));
}

Vec2 ProfileSegment::tangent_at(double u) const {
  if (kind == Kind::kLine) {
    const Vec2 d = end - start;
    const double n = d.norm();
    CWE_ASSERT(n > 0.0, "zero-length profile line");
    return d / n;
  }
  const double a = start_angle() + u * (end_angle() - start_angle());
  const Vec2 t(-std::sin(a), std::cos(a));
  return counterclockwise ? t : Vec2(-t);
}

Vec2 ProfileSegment::normal_at(double u) const {
  const Vec2 t = tangent_at(u);
  return {t.y(), -t.x()};
}

double ProfileSegment::min_z() const { return std::min(start.y(), end.y()); }
double ProfileSegment::max_z() const { return std::max(start.y(), end.y()); }

bool ProfileSegment::is_horizontal() const { return kind == Kind::kLine && start.y() == end.y(); }
bool ProfileSegment::is_vertical() const { return kind == Kind::kLine && start.x() == end.x(); }

double ProfileSegment::max_radius() const {
  double m = std::max(start.x(), end.x());
  if (kind == Kind::kArc && sweep_contains(start_angle(), end_angle(), 0.0)) {
    m = std::max(m, center.x() + radius);
  }
  return m;
}

double ProfileSegment::radius_at(double z) const {
  if (kind == Kind::kLine) {
    const double dz = end.y() - start.y();
    // A horizontal line covers one height; the solid there reaches its outer end.
    if (dz == 0.0) return std::max(start.x(), end.x());
    const double u = std::clamp((z - start.y()) / dz, 0.0, 1.0);
    return start.x() + u * (end.x() - start.x());
  }
  // A rising arc lies on one side of its centre: the right half when it turns counter-clockwise
  // (a convex corner), the left half otherwise (a concave corner).
  const double dz = std::clamp(z - center.y(), -radius, radius);
  const double w = std::sqrt(std::max(0.0, radius * radius - dz * dz));
  return counterclockwise ? center.x() + w : center.x() - w;
}

ProfileSegment::Closest ProfileSegment::closest(const Vec2& q) const {
  if (kind == Kind::kLine) {
    const Vec2 d = end - start;
    const double dd = d.squaredNorm();
    const double u = dd > 0.0 ? std::clamp((q - start).dot(d) / dd, 0.0, 1.0) : 0.0;
    return {u, (start + u * d - q).norm()};
  }
  const double a0 = start_angle();
  const double a1 = end_angle();
  const Vec2 v = q - center;
  Closest best{0.0, (start - q).norm()};
  const double d_end = (end - q).norm();
  if (d_end < best.distance) best = {1.0, d_end};
  if (v.squaredNorm() > 0.0) {
    const double a = std::atan2(v.y(), v.x());
    if (sweep_contains(a0, a1, a)) {
      const double w = wrap_from(a, std::min(a0, a1));
      const double u = (w - a0) / (a1 - a0);
      const double d = std::abs(v.norm() - radius);
      if (d < best.distance) best = {u, d};
    }
  }
  return best;
}

Profile::Profile(std::vector<ProfileSegment> segments, const std::string& source)
    : segments_(std::move(segments)) {
  const auto fail = [&](std::size_t index, const std::string& why) {
    throw InputError(SourceLocation{source},
                     index == 0 ? why : fmt::format("piece {}: {}", index, why));
  };
  if (segments_.empty()) fail(0, "a profile needs at least one piece");

  const double tol = tol::kInputLength;
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    ProfileSegment& s = segments_[i];
    const std::size_t n = i + 1;
    if (!s.start.allFinite() || !s.end.allFinite() || !s.center.allFinite()) {
      fail(n, "coordinates must be finite numbers");
    }
    // Continuity: snap each piece onto its predecessor (or the tip).
    const Vec2 expected = i == 0 ? Vec2::Zero() : segments_[i - 1].end;
    if ((s.start - expected).norm() > tol) {
      fail(n, i == 0 ? fmt::format("the profile must start at the tip (0, 0), not ({}, {})",
                                   s.start.x(), s.start.y())
                     : fmt::format("starts at ({}, {}) but the previous piece ends at ({}, {})",
                                   s.start.x(), s.start.y(), expected.x(), expected.y()));
    }
    s.start = expected;
    if ((s.end - s.start).norm() <= tol) fail(n, "has zero length");
    if (s.end.x() < -tol) fail(n, fmt::format("ends at negative radius {}", s.end.x()));
    s.end.x() = std::max(0.0, s.end.x());
    if (s.end.y() < s.start.y() - tol) {
      fail(n, fmt::format("goes down from z = {} to z = {}; a profile must rise from the tip",
                          s.start.y(), s.end.y()));
    }
    if (s.end.y() < s.start.y()) s.end.y() = s.start.y();
    if (i > 0 && s.start.x() <= 0.0) {
      fail(n, "starts on the axis: only the first piece may (the solid would be pinched)");
    }
    if (s.kind == ProfileSegment::Kind::kArc) {
      s.radius = (s.start - s.center).norm();
      if (s.radius <= tol) fail(n, "arc radius is zero");
      if (std::abs((s.end - s.center).norm() - s.radius) > tol) {
        fail(n, fmt::format("arc end is {} from the centre but its start is {}",
                            (s.end - s.center).norm(), s.radius));
      }
      // z = c_z + r sin θ rises along a counter-clockwise arc only on the right half (cos θ ≥ 0),
      // along a clockwise arc only on the left half: the sweep may not pass the top or bottom.
      const double a0 = s.start_angle();
      const double a1 = s.end_angle();
      if (sweep_contains(a0, a1, kPi / 2.0) || sweep_contains(a0, a1, -kPi / 2.0)) {
        fail(n, "arc passes through its top or bottom point: a profile must rise monotonically");
      }
      // (With neither extreme inside and z rising from start to end, a counter-clockwise arc lies
      // right of its centre and a clockwise one left of it.)
      if (!s.counterclockwise && sweep_contains(a0, a1, kPi) && s.center.x() - s.radius < -tol) {
        fail(n, "arc crosses the axis");
      }
    }
  }
  if (height() <= tol) fail(0, "the profile must rise above the tip (height > 0)");
  if (top_radius() <= 0.0) fail(0, "the profile must end away from the axis (top radius > 0)");
  CWE_ASSERT(segments_.front().start == Vec2::Zero(), "profile not snapped to the tip");
  // The flutes' cylinder, where radius_at needs no walk over the pieces: a vertical line whose
  // open height range no other piece shares (there radius_at's walk gives start + u·0, its
  // radius exactly).
  for (const ProfileSegment& piece : segments_) {
    const double lo = piece.min_z(), hi = piece.max_z();
    if (!piece.is_vertical() || !(piece.start.x() > 0.0) || !(lo < hi)) continue;
    const bool alone = std::none_of(segments_.begin(), segments_.end(), [&](const auto& other) {
      return &other != &piece && other.min_z() < hi && other.max_z() > lo;
    });
    if (!alone) continue;
    cylinder_lo_ = lo, cylinder_hi_ = hi, cylinder_radius_ = piece.start.x();
    break;
  }
  // A quarter ball at the foot: lowest_reaching needs no walk over the pieces up to its radius.
  const ProfileSegment& foot = segments_.front();
  if (foot.kind == ProfileSegment::Kind::kArc && foot.counterclockwise && foot.radius > 0.0 &&
      foot.center == Vec2(0.0, foot.radius) && foot.start == Vec2::Zero() &&
      foot.end == Vec2(foot.radius, foot.radius)) {
    foot_ball_radius_ = foot.radius;
  }
  // Each piece gives heights_reaching the same heights for every r up to a radius of its own: a
  // level line its point while either end reaches r, another line its height range while both
  // ends do, a convex arc its height range while r is at most its centre's radius. A concave
  // arc's answer turns on a root for every r (no such radius).
  double reach_all = std::numeric_limits<double>::infinity();
  for (const ProfileSegment& s : segments_) {
    if (s.kind == ProfileSegment::Kind::kLine) {
      const double r0 = s.start.x(), r1 = s.end.x();
      reach_all = std::min(reach_all, s.min_z() == s.max_z() ? std::max(r0, r1) : std::min(r0, r1));
    } else {
      reach_all = s.counterclockwise ? std::min(reach_all, s.center.x())
                                     : -std::numeric_limits<double>::infinity();
    }
  }
  reach_all_heights_ = heights_reaching(reach_all);
  reach_all_ = reach_all;
}

double Profile::max_radius() const {
  double m = 0.0;
  for (const auto& s : segments_) m = std::max(m, s.max_radius());
  return m;
}

double Profile::length() const {
  double total = 0.0;
  for (const auto& s : segments_) total += s.length();
  return total;
}

double Profile::radius_at(double z) const {
  if (z > cylinder_lo_ && z < cylinder_hi_) return cylinder_radius_;  // most asks: the flutes
  if (!(z >= 0.0 && z <= height())) return 0.0;
  double r = 0.0;
  for (const auto& s : segments_) {
    if (z >= s.min_z() && z <= s.max_z()) r = std::max(r, s.radius_at(z));
  }
  return r;
}

Interval Profile::heights_reaching(double r) const {
  if (r <= reach_all_) return reach_all_heights_;
  Interval heights = Interval::empty();
  for (const ProfileSegment& s : segments_) {
    const double z0 = s.min_z(), z1 = s.max_z();
    if (s.kind == ProfileSegment::Kind::kLine) {
      const double r0 = s.start.x(), r1 = s.end.x();  // at z0 and z1: the profile rises
      if (z0 == z1) {
        if (std::max(r0, r1) >= r) heights = hull(heights, Interval::point(z0));
      } else if (r0 >= r && r1 >= r) {
        heights = hull(heights, Interval{z0, z1});
      } else if (r0 >= r || r1 >= r) {
        const double zc = std::clamp(z0 + (r - r0) / (r1 - r0) * (z1 - z0), z0, z1);
        heights = hull(heights, r0 >= r ? Interval{z0, zc} : Interval{zc, z1});
      }
      continue;
    }
    // ρ(z) = c ± √(R² - (z - c_z)²) ≥ r: within w of c_z on a convex corner (+), beyond it on a
    // concave one (-), where w² = R² - (r - c)².
    const double excess = r - s.center.x();
    const double w2 = s.radius * s.radius - excess * excess;
    if (s.counterclockwise) {
      if (excess <= 0.0) {
        heights = hull(heights, Interval{z0, z1});
      } else if (w2 >= 0.0) {
        const double w = std::sqrt(w2);
        heights = hull(heights, intersect(Interval{s.center.y() - w, s.center.y() + w}, {z0, z1}));
      }
      continue;
    }
    if (excess > 0.0) continue;  // the concave piece stays inside ρ = c
    if (w2 <= 0.0) {
      heights = hull(heights, Interval{z0, z1});
      continue;
    }
    const double w = std::sqrt(w2);
    heights = hull(heights, intersect(Interval{z0, z1}, {z0, s.center.y() - w}));
    heights = hull(heights, intersect(Interval{z0, z1}, {s.center.y() + w, z1}));
  }
  return heights;
}

double Profile::lowest_reaching(double r) const {
  if (const double big = foot_ball_radius_; big > 0.0 && r <= big) {
    // heights_reaching's steps on the foot's arc (centre (0, R), heights 0 to R), which holds
    // the lowest answer: every other piece lies at R or above. r ≤ 0 reaches from the tip.
    if (!(r > 0.0)) return 0.0;
    return std::max(big - std::sqrt(big * big - r * r), 0.0);
  }
  const Interval heights = heights_reaching(r);
  return heights.is_empty() ? 0.0 : heights.lo;
}

bool Profile::contains(double rho, double z) const {
  if (!(z >= 0.0 && z <= height())) return false;
  return rho <= radius_at(z);
}

double Profile::signed_distance(double rho, double z) const {
  const Vec2 q(rho, z);
  const Vec2 top(std::clamp(rho, 0.0, top_radius()), height());
  const double d = std::min(closest(q).distance, (q - top).norm());
  return contains(rho, z) ? -d : d;
}

Profile::Location Profile::closest(const Vec2& q) const {
  Location best{0, 0.0, std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    const auto c = segments_[i].closest(q);
    if (c.distance < best.distance) best = {static_cast<int>(i), c.u, c.distance};
  }
  return best;
}

}  // namespace cwe
