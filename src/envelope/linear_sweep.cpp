#include "cwe/envelope/linear_sweep.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "cwe/core/assert.hpp"
#include "cwe/core/error.hpp"
#include "cwe/envelope/swept_volume.hpp"
#include "cwe/geometry/intersect.hpp"
#include "cwe/geometry/quotient.hpp"
#include "cwe/geometry/roots.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/tool/piece_chord.hpp"

namespace cwe {
namespace {

// The crossing function of an arc's swept grazing curve has at most a few extrema over a quarter
// circle; kArcSamples = 24 samples bracket every transversal crossing, and a tangent touch that
// falls between samples only loses a degenerate point of the chord, which the neighbouring
// surfaces then supply.

struct Hull {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double t) {
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  void add(const Interval& i) {
    if (i.is_empty()) return;
    add(i.lo);
    add(i.hi);
  }
  Interval interval() const { return lo <= hi ? Interval{lo, hi} : Interval::empty(); }
};

// Solves o + t d = p + λ D for (t, λ) given that p lies in the plane spanned by d and D through
// o: least squares on the 2 × 2 normal equations (exact for coplanar data).
bool solve_in_plane(const Vec3& d, const Vec3& D, const Vec3& rhs, double& t, double& lambda) {
  // [d, -D] (t, λ)ᵀ = rhs
  const double a11 = d.dot(d), a12 = -d.dot(D), a22 = D.dot(D);
  const double b1 = d.dot(rhs), b2 = -D.dot(rhs);
  const double det = a11 * a22 - a12 * a12;
  if (!(std::abs(det) > tol::kRelative * a11 * a22)) return false;
  t = (b1 * a22 - a12 * b2) / det;
  lambda = (a11 * b2 - a12 * b1) / det;
  return true;
}

// Narrows `chord` to the parameters where s0 + t·ds lies in [lo, hi].
[[gnu::always_inline]] inline void clip(Interval& chord, double s0, double ds, double lo,
                                        double hi) {
  if (ds == 0.0) {
    if (s0 < lo || s0 > hi) chord = Interval::empty();
    return;
  }
  // Axis-aligned paths and rays spare their divisions.
  const double a = quotient_by_unit(lo - s0, ds), b = quotient_by_unit(hi - s0, ds);
  chord = intersect(chord, Interval{std::min(a, b), std::max(a, b)});
}

// The 2-D line o + t d (d ≠ 0) through the disc |p - c| ≤ r.
[[gnu::always_inline]] inline Interval disc_chord(const Vec2& o, const Vec2& d, const Vec2& c,
                                                  double r) {
  const Vec2 w = o - c;
  const double a = d.squaredNorm();
  const double cross = d.x() * w.y() - d.y() * w.x();
  const double gap = r * r - cross * cross / a;  // r² minus the squared distance to c
  if (gap < 0.0) return Interval::empty();
  const double middle = -w.dot(d) / a;
  const double half = std::sqrt(gap / a);
  return {middle - half, middle + half};
}

// The capsule of radius r about the segment c0–c1 in a plane, with what its chords share.
struct Capsule {
  Vec2 c0 = Vec2::Zero(), c1 = Vec2::Zero();
  double length = 0.0;
  Vec2 e = Vec2::Zero(), n = Vec2::Zero();  // unit vectors along the segment and square to it
  Capsule() = default;
  Capsule(const Vec2& from, const Vec2& to) : c0(from), c1(to) {
    const Vec2 along = c1 - c0;
    length = along.norm();
    if (length > 0.0) {
      e = along / length;
      n = Vec2(-e.y(), e.x());
    }
  }
  // The 2-D line o + t d (d ≠ 0) through it (convex: the hull of the chords through both end
  // discs and the rectangle between them). Inlined, so that a d known where it is called (a ray
  // along X or Y) spares what multiplies by 1 or divides by |d|² = 1.
  [[gnu::always_inline]] Interval chord(const Vec2& o, const Vec2& d, double r) const {
    Hull hull;
    hull.add(disc_chord(o, d, c0, r));
    hull.add(disc_chord(o, d, c1, r));
    if (length > 0.0) {
      Interval band = Interval::full();
      clip(band, (o - c0).dot(e), d.dot(e), 0.0, length);
      clip(band, (o - c0).dot(n), d.dot(n), -r, r);
      hull.add(band);
    }
    return hull.interval();
  }
};

// The 2-D line through the capsule of radius r about the segment c0–c1.
Interval capsule_chord(const Vec2& o, const Vec2& d, const Vec2& c0, const Vec2& c1, double r) {
  return Capsule(c0, c1).chord(o, d, r);
}

// A ball of radius r swept along D from the centre c: where the ray o + t·d (rel = o - c)
// crosses the cylinder of radius r about the centre's path with its foot on the path between
// the two end balls, at path fraction λ ∈ [0, 1]: visit(t, λ·|D|²) for each (at most two).
// `feed2` is |D|², m the direction's part square to D and a = |m|² (fixed for a move and a
// direction: swept_ball_side below finds them).
template <class Visit>
void swept_ball_side(const Vec3& rel, const Vec3& d, const Vec3& feed, double feed2, const Vec3& m,
                     double a, double r, Visit&& visit) {
  if (!(feed2 > 0.0) || !(a > 0.0)) return;
  const Vec3 p0 = rel - (rel.dot(feed) / feed2) * feed;
  const double b = p0.dot(m);
  const double disc = b * b - a * (p0.squaredNorm() - r * r);
  if (disc < 0.0) return;
  const double root = std::sqrt(disc);
  // x / 1 is x: a ray square to the feed spares the divisions.
  const auto over_a = [a](double x) { return a == 1.0 ? x : x / a; };
  for (const double t : {over_a(-b - root), over_a(-b + root)}) {
    const double along = (rel + t * d).dot(feed);
    if (quotient_in_unit(along, feed2)) visit(t, along);
  }
}

// The direction's part square to the feed (for swept_ball_side).
Vec3 square_to_feed(const Vec3& d, const Vec3& feed, double feed2) {
  return d - (d.dot(feed) / feed2) * feed;
}

template <class Visit>
void swept_ball_side(const Vec3& rel, const Vec3& d, const Vec3& feed, double r, Visit&& visit) {
  const double feed2 = feed.squaredNorm();
  if (!(feed2 > 0.0)) return;
  const Vec3 m = square_to_feed(d, feed, feed2);
  swept_ball_side(rel, d, feed, feed2, m, m.squaredNorm(), r, visit);
}

}  // namespace

LinearSweep::LinearSweep(const Cutter& cutter, const Vec3& start, const Vec3& end, const Vec3& axis)
    : cutter_(&cutter), start_(start), end_(end) {
  if (!is_convex(cutter)) {
    throw InputError(SourceLocation{cutter.name()},
                     "material removal needs a convex cutter (every APT cutter is one)");
  }
  const Vec3 feed = end - start;
  const Vec3 lateral = feed - axis * axis.dot(feed);
  tcs_ = Frame::from_z(start, axis, lateral.norm() > tol::kLength ? lateral : Vec3::UnitX());
  delta_ = tcs_.direction_to_local(feed);
  // Box of the bounding cylinder at both ends.
  const BoundingCylinder b = cutter.bounding_cylinder();
  for (const Vec3& tip : {start, end}) {
    for (const double z : {b.z_min, b.z_max}) {
      const Vec3 c = tip + z * axis;
      // A disc of radius r about unit axis n extends r·√(1 - n_i²) along axis i.
      const Vec3 extent =
          (Vec3::Ones() - axis.cwiseProduct(axis)).cwiseMax(0.0).cwiseSqrt() * b.radius;
      bounds_.extend(c - extent);
      bounds_.extend(c + extent);
    }
  }

  // Per-move data of the general construction: profile vertices, the grazing generators of line
  // pieces and the sampled grazing curves of arcs.
  const auto& segments = cutter.profile().segments();
  vertices_.push_back(segments.front().start);
  for (const auto& s : segments) vertices_.push_back(s.end);
  lateral_ = std::hypot(delta_.x(), delta_.y());
  phase_ = std::atan2(delta_.y(), delta_.x());
  if (lateral_ > tol::kLength) {
    for (std::size_t i = 0; i < segments.size(); ++i) {
      const ProfileSegment& segment = segments[i];
      for (int branch = 0; branch < 2; ++branch) {
        if (segment.kind == ProfileSegment::Kind::kLine) {
          bool exists = false;
          const Vec3 a = grazing_point(static_cast<int>(i), branch, 0.0, exists);
          if (!exists) continue;
          generators_.push_back({a, grazing_point(static_cast<int>(i), branch, 1.0, exists)});
          continue;
        }
        if (segment.center.x() <= 0.0) {  // a sphere: one closed-form piece for both branches
          if (branch == 0) {
            spheres_.push_back(
                {segment.center.y(), segment.radius, segment.min_z(), segment.max_z()});
          }
          continue;
        }
        GrazingSamples samples;
        samples.segment = static_cast<int>(i);
        samples.branch = branch;
        for (int k = 0; k <= kArcSamples; ++k) {
          bool exists = false;
          samples.point[static_cast<std::size_t>(k)] =
              grazing_point(samples.segment, branch, static_cast<double>(k) / kArcSamples, exists);
          samples.exists[static_cast<std::size_t>(k)] = exists;
        }
        // The curve exists where |n_z·D_z| ≤ |n_ρ·lateral|, i.e. |tan θ| ≤ lateral/|D_z| for the
        // normal's angle θ, which is linear in u along the arc. Between two samples where it
        // exists at neither end and n_z keeps its strict sign, θ stays within one interval
        // (0, π) mod π, on which |tan θ| is smallest at an end: no point between exists, and a
        // sign change of the crossing function there is no grazing point (the search for it
        // was most of a tilted bull nose's chord time).
        for (int k = 1; k <= kArcSamples; ++k) {
          const auto kk = static_cast<std::size_t>(k);
          const double z0 = segment.normal_at(static_cast<double>(k - 1) / kArcSamples).y();
          const double z1 = segment.normal_at(static_cast<double>(k) / kArcSamples).y();
          samples.none_between[kk] = !samples.exists[kk - 1] && !samples.exists[kk] &&
                                     ((z0 > 0.0 && z1 > 0.0) || (z0 < 0.0 && z1 < 0.0));
        }
        arcs_.push_back(samples);
      }
    }
  }

  // Closed forms for a tool standing along +Z.
  const bool vertical = std::abs(axis.x()) <= tol::kRelative &&
                        std::abs(axis.y()) <= tol::kRelative && axis.z() > 0.0;
  vertical_axis_ = vertical;
  plan_radius_ = cutter.profile().max_radius();
  if (vertical) {
    if (start.z() == end.z()) {
      mode_ = Mode::kLevel;
    } else if (start.x() == end.x() && start.y() == end.y()) {
      mode_ = Mode::kAxial;
    }
  }
  if (vertical) {
    // The height of the widest section (R is concave: any maximiser serves).
    double widest = -1.0;
    for (const auto& s : segments) {
      for (const double h : {s.min_z(), s.max_z(), std::clamp(s.center.y(), s.min_z(), s.max_z())}) {
        const double r = cutter.profile().radius_at(h);
        if (r > widest) widest = r, widest_height_ = h;
      }
    }
    // A ball end with its whole ball inside the tool (the cylinder reaches 2R above the tip).
    const double r = cutter.profile().max_radius();
    if (mode_ == Mode::kGeneric && segments.size() == 2 &&
        segments[0].kind == ProfileSegment::Kind::kArc && segments[0].center == Vec2(0.0, r) &&
        segments[0].radius == r && segments[0].start == Vec2(0.0, 0.0) &&
        segments[0].end == Vec2(r, r) && segments[1].kind == ProfileSegment::Kind::kLine &&
        segments[1].start == Vec2(r, r) && segments[1].end.x() == r &&
        segments[1].end.y() >= 2.0 * r) {
      ball_radius_ = r;
      ball_top_ = segments[1].end.y();
      ball_feed_ = end_ - start_;
      ball_centres_ = {start_ + Vec3(0.0, 0.0, r), Vec3(start_ + Vec3(0.0, 0.0, r) + ball_feed_)};
      ball_feed2_ = ball_feed_.squaredNorm();
      for (int a = 0; a < 3; ++a) {
        const auto k = static_cast<std::size_t>(a);
        ball_square_[k] = square_to_feed(Vec3::Unit(a), ball_feed_, ball_feed2_);
        ball_square2_[k] = ball_square_[k].squaredNorm();
      }
    }
    // The tip's path in plan (level chords; every move's row_span).
    path_start_ = start.head<2>();
    const Vec2 along = end.head<2>() - path_start_;
    path_length_ = along.norm();
    path_along_ = path_length_ > 0.0 ? Vec2(along / path_length_) : Vec2(1.0, 0.0);
  }
}

Vec3 LinearSweep::grazing_point(int segment_index, int branch, double u, bool& exists) const {
  // The tangency function of a translation (tangency_coefficients with ω = 0) in amplitude-phase
  // form, its phase fixed per move: N·D = n_ρ·lateral·sin(φ + phase) + n_z D_z = 0 on branch 0
  // or 1, continued past the curve's end as sin_cos_branch says. Horizontal faces (n_ρ = 0)
  // have no grazing curve.
  const ProfileSegment& segment =
      cutter_->profile().segments()[static_cast<std::size_t>(segment_index)];
  const Vec2 normal = segment.normal_at(u);
  const Vec2 p = segment.point_at(u);
  exists = false;
  const double phi = std::abs(normal.x()) > tol::kAngle
                         ? sin_cos_branch(normal.x() * lateral_, phase_, normal.y() * delta_.z(),
                                          branch, exists)
                         : 0.0;
  return {p.x() * std::sin(phi), p.x() * std::cos(phi), p.y()};
}

Interval LinearSweep::capsule_span(const Vec3& o, int along, double r) const {
  // Coordinates: s along the ray's axis, q across it; the ray is the line q = o_q.
  const int across = 1 - along;
  const Vec2 c0 = path_start_, c1 = path_start_ + path_length_ * path_along_;
  // Paths along X or Y (most of a pocket's moves) in closed form, with the same numbers as the
  // general hull below: a unit or zero component makes its products and quotients exact.
  if (path_along_[across] == 0.0) {
    // Along the ray (|e_s| = 1, so c1_q = c0_q): the two end discs' chords are alike, and the
    // rectangle adds only c0_s and c1_s, which lie between them.
    const double dq = o[across] - c0[across];
    const double gap = r * r - dq * dq;
    if (gap < 0.0) return Interval::empty();
    const double half = std::sqrt(gap);
    return {std::min(c0[along], c1[along]) - half, std::max(c0[along], c1[along]) + half};
  }
  if (path_along_[along] == 0.0) {
    // Across the ray (|e_q| = 1, so c1_s = c0_s): the rectangle's chord, ±r about c0_s, holds
    // the discs' where the ray passes beside the path; beyond its ends, the nearer disc's.
    if (const double beside = (o[across] - c0[across]) * path_along_[across];
        !(beside < 0.0 || beside > path_length_)) {
      return {c0[along] - r, c0[along] + r};
    }
    double half = -1.0;
    for (const double q : {c0[across], c1[across]}) {
      const double dq = o[across] - q;
      const double gap = r * r - dq * dq;
      if (gap >= 0.0) half = std::max(half, std::sqrt(gap));
    }
    if (half < 0.0) return Interval::empty();
    return {c0[along] - half, c0[along] + half};
  }
  Hull hull;
  for (const Vec2& c : {c0, c1}) {
    const double dq = o[across] - c[across];
    const double gap = r * r - dq * dq;
    if (gap < 0.0) continue;
    const double half = std::sqrt(gap);
    hull.add(c[along] - half), hull.add(c[along] + half);
  }
  if (path_length_ > 0.0) {
    // The rectangle: 0 ≤ (p - c0)·e ≤ L and |(p - c0)·n| ≤ r, each linear in s.
    const Vec2 e = path_along_, n(-e.y(), e.x());
    const double dq = o[across] - c0[across];
    Interval band = Interval::full();
    clip(band, dq * e[across], e[along], 0.0, path_length_);
    clip(band, dq * n[across], n[along], -r, r);
    if (!band.is_empty()) hull.add(c0[along] + band.lo), hull.add(c0[along] + band.hi);
  }
  return hull.interval();
}

Interval LinearSweep::level_axis_chord(const Vec3& o, int along, double sign, double r) const {
  // The capsule's extent on the ray's line, then t = ±(x - o_x).
  const Interval span = capsule_span(o, along, r);
  if (span.is_empty()) return span;
  const double a = sign * (span.lo - o[along]), b = sign * (span.hi - o[along]);
  return {std::min(a, b), std::max(a, b)};
}

Interval LinearSweep::level_chord(const Ray& ray) const {
  const Vec3& o = ray.origin;
  const Vec3& d = ray.direction;
  const Profile& profile = cutter_->profile();
  if (d.z() == 0.0) {
    const double h = o.z() - start_.z();
    if (!(h >= 0.0 && h <= profile.height())) return Interval::empty();
    const double r = profile.radius_at(h);
    const int along = d.y() == 0.0 ? 0 : 1;
    // Along world X or Y: in closed form.
    if (d.squaredNorm() == 1.0 && d[1 - along] == 0.0) {
      return level_axis_chord(o, along, d[along], r);
    }
    return capsule_chord(o.head<2>(), d.head<2>(), start_.head<2>(), end_.head<2>(), r);
  }
  return level_vertical_chord(o.head<2>(), o.z(), d.z());
}

Interval LinearSweep::level_vertical_chord(const Vec2& q, double oz, double dz) const {
  // Its distance from the tip's path decides the heights it meets.
  const Vec2 c0 = start_.head<2>(), c1 = end_.head<2>();
  const Vec2 along = c1 - c0;
  const double length2 = along.squaredNorm();
  const double u = length2 > 0.0 ? clamped_quotient((q - c0).dot(along), length2) : 0.0;
  const Interval h = cutter_->profile().heights_reaching((q - c0 - u * along).norm());
  if (h.is_empty()) return h;
  // The ray's parameters at those heights (a stock's rays run along ±Z).
  const double a = quotient_by_unit(start_.z() + h.lo - oz, dz);
  const double b = quotient_by_unit(start_.z() + h.hi - oz, dz);
  return {std::min(a, b), std::max(a, b)};
}

// The swept cylinder's section at a height: the plan capsule of its discs at the path
// parameters u0 to u1 whose heights hold it.
struct LinearSweep::BallLevel {
  bool made = false;
  std::uint64_t u0 = 0, u1 = 0;  // the parameters' bits (a zero's sign too)
  Capsule capsule;
};

template <int A>
Interval LinearSweep::ball_chord(const Vec3& o, const Vec3& given, BallLevel* level) const {
  static_assert(A >= -1 && A <= 2);
  const Vec3 d = A < 0 ? given : Vec3(A == 0 ? 1.0 : 0.0, A == 1 ? 1.0 : 0.0, A == 2 ? 1.0 : 0.0);
  const double r = ball_radius_, top = ball_top_;
  const Vec3& feed = ball_feed_;
  const Vec2 plan = feed.head<2>();
  const bool vertical = d.x() == 0.0 && d.y() == 0.0;
  // A horizontal ray meets the cylinder (radius r, heights r to `top` above the tip, its plan
  // disc about start + u·feed at the path parameter u and its heights shifted by u·feed_z) at
  // the u whose heights hold the ray's: u0 to u1, where `section`.
  const double h = o.z() - start_.z();
  double u0 = 0.0, u1 = 1.0;
  bool section = !vertical;
  if (const double fz = feed.z(); section && fz != 0.0) {
    // u0 = max(0, min(first, last)) and u1 = min(1, max(first, last)) with first = (h - top)/fz
    // and last = (h - r)/fz (first < last where fz > 0, r < top). Where the quotient's sign or
    // its side of 1 decides them (the heights the cylinder spans over the whole move), without
    // the division: the same numbers.
    const double above = h - top, below = h - r;
    if (fz > 0.0) {
      u0 = above <= 0.0 ? 0.0 : std::max(0.0, above / fz);
      u1 = below >= fz ? 1.0 : std::min(1.0, below / fz);
    } else {
      u0 = below >= 0.0 ? 0.0 : std::max(0.0, below / fz);
      u1 = above <= fz ? 1.0 : std::min(1.0, above / fz);
    }
    section = u0 <= u1;
  } else if (section) {
    section = !(h < r || h > top);
  }
  Hull hull;
  // The ball's capsule (the balls at both ends, and the cylinder of radius r about the centre's
  // path where the ray meets it between the two ends), but for a ray along X or Y where the
  // cylinder's section spans the whole move and the ray passes at least kBallClearance·r above
  // both centres (m = kBallClearance·r): every point of the ball's capsule at that height lies
  // within √(r² − m²) of the tip's path in plan, g = r − √(r² − m²) ≈ 1.2e-3·r inside the
  // section's capsule, and the ray's crossings with it lie that far inside the section's chord,
  // ten thousand times the rounding of either construction (≈ 5e-8·r at a tangent, where a
  // root's argument loses its digits): the hull is the section's chord alone, to the last bit.
  const bool ball_inside = (A == 0 || A == 1) && section && u0 == 0.0 && u1 == 1.0 &&
                           h >= r + std::max(0.0, feed.z()) + kBallClearance * r;
  if (!ball_inside) {
    // The end balls by their quadratic: intersect(Ray, Sphere) gives the same chords with a
    // tangency allowance removal has no use for (a touching ray removes nothing), and cost a
    // quarter of a ball raster's removal time here.
    const double a = d.squaredNorm();
    for (const Vec3& c : ball_centres_) {
      const Vec3 w = o - c;
      const double b = w.dot(d), gap = b * b - a * (w.squaredNorm() - r * r);
      if (gap < 0.0) continue;
      const double root = std::sqrt(gap);
      hull.add((-b - root) / a), hull.add((-b + root) / a);
    }
    const auto visit = [&](double t, double) { hull.add(t); };
    if constexpr (A < 0) {
      swept_ball_side(o - ball_centres_[0], d, feed, r, visit);
    } else {
      swept_ball_side(o - ball_centres_[0], d, feed, ball_feed2_, ball_square_[A], ball_square2_[A],
                      r, visit);
    }
  }
  if (vertical) {
    // A vertical ray: the u whose disc holds the ray's plan point, then their heights' hull.
    const Vec2 q = o.head<2>() - start_.head<2>();
    const double p2 = plan.squaredNorm(), b = q.dot(plan), c = q.squaredNorm() - r * r;
    double v0 = 0.0, v1 = 1.0;
    if (p2 > 0.0) {
      const double gap = b * b - p2 * c;
      if (gap < 0.0) return hull.interval();
      const double root = std::sqrt(gap);
      // Where the quotient's sign or its side of 1 decides them, without the division.
      v0 = b - root <= 0.0 ? 0.0 : std::max(0.0, (b - root) / p2);
      v1 = b + root >= p2 ? 1.0 : std::min(1.0, (b + root) / p2);
    } else if (c > 0.0) {
      return hull.interval();
    }
    if (v0 > v1) return hull.interval();
    const double low = start_.z() + r + std::min(v0 * feed.z(), v1 * feed.z());
    const double high = start_.z() + top + std::max(v0 * feed.z(), v1 * feed.z());
    hull.add((low - o.z()) / d.z()), hull.add((high - o.z()) / d.z());
    return hull.interval();
  }
  // A horizontal ray: the plan capsule of the section's discs.
  if (!section) return hull.interval();
  BallLevel here;
  BallLevel& kept = level != nullptr ? *level : here;
  if (const auto b0 = std::bit_cast<std::uint64_t>(u0), b1 = std::bit_cast<std::uint64_t>(u1);
      !kept.made || kept.u0 != b0 || kept.u1 != b1) {
    kept = {true, b0, b1, Capsule(start_.head<2>() + u0 * plan, start_.head<2>() + u1 * plan)};
  }
  hull.add(kept.capsule.chord(o.head<2>(), d.head<2>(), r));
  return hull.interval();
}

template <int A>
void LinearSweep::ball_chords(Ray ray, int across, std::span<const double> at,
                              std::span<Interval> chords) const {
  const bool vertical = A == 2, horizontal = A != 2;
  BallLevel level;
  Floor floor;
  const Vec3& o = ray.origin;
  for (std::size_t k = 0; k < at.size(); ++k) {
    // Each ray made whole (see chords()).
    const Ray each{
        Vec3(across == 0 ? at[k] : o.x(), across == 1 ? at[k] : o.y(), across == 2 ? at[k] : o.z()),
        ray.direction};
    chords[k] = out_of_reach(each, vertical, horizontal, &floor)
                    ? Interval::empty()
                    : ball_chord<A>(each.origin, each.direction, &level);
  }
}

Interval LinearSweep::axial_chord(const Ray& ray) const {
  const Vec3& o = ray.origin;
  const Vec3& d = ray.direction;
  const Profile& profile = cutter_->profile();
  const double z_low = std::min(start_.z(), end_.z()), z_high = std::max(start_.z(), end_.z());
  if (d.z() == 0.0) {
    // The heights above the tip that pass the ray's level during the move.
    const double a = std::max(0.0, o.z() - z_high), b = std::min(profile.height(), o.z() - z_low);
    if (!(a <= b)) return Interval::empty();
    const double r = profile.radius_at(std::clamp(widest_height_, a, b));
    return disc_chord(o.head<2>(), d.head<2>(), start_.head<2>(), r);
  }
  const Interval h = cutter_->profile().heights_reaching((o.head<2>() - start_.head<2>()).norm());
  if (h.is_empty()) return h;
  const double a = (z_low + h.lo - o.z()) / d.z(), b = (z_high + h.hi - o.z()) / d.z();
  return {std::min(a, b), std::max(a, b)};
}

Interval LinearSweep::chord(const Ray& ray) const {
  const Vec3& d = ray.direction;
  const bool horizontal = d.z() == 0.0 && (d.x() != 0.0 || d.y() != 0.0);
  const bool vertical = d.x() == 0.0 && d.y() == 0.0 && d.z() != 0.0;
  if (mode_ == Mode::kLevel && (horizontal || vertical)) return level_chord(ray);
  if (mode_ == Mode::kAxial && (horizontal || vertical)) return axial_chord(ray);
  if (out_of_reach(ray, vertical, horizontal)) return Interval::empty();
  if (ball_radius_ > 0.0 && (vertical || (horizontal && (d.x() == 0.0 || d.y() == 0.0)))) {
    if (d == Vec3::UnitX()) return ball_chord<0>(ray.origin, d);
    if (d == Vec3::UnitY()) return ball_chord<1>(ray.origin, d);
    if (d == Vec3::UnitZ()) return ball_chord<2>(ray.origin, d);
    return ball_chord<-1>(ray.origin, d);
  }
  return generic_chord(ray);
}

bool LinearSweep::out_of_reach(const Ray& ray, bool vertical, bool horizontal, Floor* last) const {
  const Vec3& d = ray.direction;
  if (vertical && vertical_axis_) {
    // Every point of a tool standing along +Z lies within its largest radius of the axis, whose
    // plan position is the tip's: a vertical ray farther than that from the tip's path in plan
    // misses the sweep (the box around a climbing move holds many such rays). Squared, without
    // a root: the allowance is far above the difference.
    const double reach = plan_radius_ * (1.0 + tol::kRelative) + tol::kLength;
    if (plan_gap2(ray.origin) > reach * reach) return true;
  } else if (horizontal && vertical_axis_ && (d.x() == 0.0 || d.y() == 0.0)) {
    // A ray along world X or Y passes every axis position at least `gap` away in plan (its
    // offset across from the tip path's range), so every tool point on it stands at least
    // h_lo(gap) above its tip, h_lo(r) the lowest height where the tool is r wide (it grows
    // with r for a convex tool): below min tip z + h_lo(gap) the ray misses the sweep.
    const int across = d.x() == 0.0 ? 0 : 1;
    const double a0 = std::min(start_[across], end_[across]);
    const double a1 = std::max(start_[across], end_[across]);
    const double o = ray.origin[across];
    const double gap = o < a0 ? a0 - o : (o > a1 ? o - a1 : 0.0);
    if (gap > plan_radius_ * (1.0 + tol::kRelative) + tol::kLength) return true;
    Floor here;
    Floor& floor = last != nullptr ? *last : here;
    if (const auto bits = std::bit_cast<std::uint64_t>(gap); !floor.made || floor.gap != bits) {
      floor = {true, bits,
               std::min(start_.z(), end_.z()) + cutter_->profile().lowest_reaching(gap)};
    }
    const double lowest = floor.z;
    if (ray.origin.z() < lowest - tol::kLength * (1.0 + std::abs(lowest) / tol::kModelScale)) {
      return true;
    }
  }
  return false;
}

void LinearSweep::chords(Ray ray, int across, std::span<const double> at,
                         std::span<Interval> chords) const {
  CWE_ASSERT(at.size() == chords.size(), "one chord per ray");
  const Vec3& d = ray.direction;
  Vec3& o = ray.origin;
  int along = 0;
  if (level_axis_rays(d, along)) {
    // Level rays along world X or Y: level_chord's steps without its tests, and where the rays
    // share their height (a row across them in plan), one radius for the row.
    double r = 0.0;
    const bool level_row = across != 2;
    const bool reached = level_row && level_radius(o.z(), r);
    if (level_row) {
      for (std::size_t k = 0; k < at.size(); ++k) {
        o[across] = at[k];
        chords[k] = reached ? level_axis_chord(o, along, d[along], r) : Interval::empty();
      }
      return;
    }
    // A row up the tool (rays at one plan position): the chord depends on the height only
    // through the radius there, so rays of the same radius (a cylindrical part) share it.
    double last_r = -1.0;
    Interval last = Interval::empty();
    for (std::size_t k = 0; k < at.size(); ++k) {
      o[across] = at[k];
      if (!level_radius(o.z(), r)) {
        chords[k] = Interval::empty();
        continue;
      }
      if (r != last_r) {
        last = level_axis_chord(o, along, d[along], r);
        last_r = r;
      }
      chords[k] = last;
    }
    return;
  }
  if (mode_ == Mode::kLevel && d.x() == 0.0 && d.y() == 0.0 && d.z() != 0.0 && across != 2) {
    // The plan point made whole, not written into the origin and read back as a pair (which
    // stalled on the store).
    for (std::size_t k = 0; k < at.size(); ++k) {
      const Vec2 q = across == 0 ? Vec2(at[k], o.y()) : Vec2(o.x(), at[k]);
      chords[k] = level_vertical_chord(q, o.z(), d.z());
    }
    return;
  }
  if (ball_radius_ > 0.0) {
    // A ball end's chords on rays along +X, +Y or +Z, with what they share found once.
    if (d == Vec3::UnitX()) return ball_chords<0>(ray, across, at, chords);
    if (d == Vec3::UnitY()) return ball_chords<1>(ray, across, at, chords);
    if (d == Vec3::UnitZ()) return ball_chords<2>(ray, across, at, chords);
  }
  for (std::size_t k = 0; k < at.size(); ++k) {
    // Each ray made whole (see above).
    const Ray each{
        Vec3(across == 0 ? at[k] : o.x(), across == 1 ? at[k] : o.y(), across == 2 ? at[k] : o.z()),
        d};
    chords[k] = chord(each);
  }
}

Interval LinearSweep::row_span(const Ray& ray, int across) const {
  const Vec3& d = ray.direction;
  if (!vertical_axis_ || d.x() != 0.0 || d.y() != 0.0 || d.z() == 0.0 || across == 2) {
    return Interval::full();
  }
  // The tool lies within its largest radius of its axis, whose plan position runs along the
  // tip's path in plan: a vertical ray farther than that from the path misses the sweep. chord()
  // gives such rays an allowance (plan_gap2, in other arithmetic); the span adds as much again.
  return capsule_span(ray.origin, across,
                      plan_radius_ * (1.0 + tol::kRelative) + 2.0 * tol::kLength);
}

bool LinearSweep::level_axis_rays(const Vec3& d, int& along) const {
  along = d.y() == 0.0 ? 0 : 1;
  return mode_ == Mode::kLevel && d.z() == 0.0 && d.squaredNorm() == 1.0 && d[1 - along] == 0.0;
}

bool LinearSweep::level_radius(double z, double& r) const {
  const Profile& profile = cutter_->profile();
  const double h = z - start_.z();
  if (!(h >= 0.0 && h <= profile.height())) return false;
  r = profile.radius_at(h);
  return true;
}

double LinearSweep::row_key(const Ray& ray, int across) const {
  int along = 0;
  double r = 0.0;
  if (across == 2 || !level_axis_rays(ray.direction, along)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return level_radius(ray.origin.z(), r) ? r : -1.0;
}

double LinearSweep::plan_gap2(const Vec3& p) const {
  const Vec2 q = p.head<2>() - start_.head<2>(), along = (end_ - start_).head<2>();
  const double length2 = along.squaredNorm();
  const double u = length2 > 0.0 ? clamped_quotient(q.dot(along), length2) : 0.0;
  return (q - u * along).squaredNorm();
}

Interval LinearSweep::reach(const Ray& ray) const {
  const Vec3& d = ray.direction;
  if (!has_reach() || d.x() != 0.0 || d.y() != 0.0 || d.z() == 0.0) return Interval::full();
  // Every tool point over plan point q stands at least h_lo(gap) above its tip (see chord()).
  const double gap2 = plan_gap2(ray.origin);
  const double reach = plan_radius_ * (1.0 + tol::kRelative) + tol::kLength;
  if (gap2 > reach * reach) return Interval::empty();
  const double lowest = cutter_->profile().lowest_reaching(std::sqrt(gap2));
  const double floor = std::min(start_.z(), end_.z()) + lowest;
  const double margin = tol::kLength * (1.0 + std::abs(floor) / tol::kModelScale);
  const double t = (floor - margin - ray.origin.z()) / d.z();
  return d.z() > 0.0 ? Interval{t, Interval::full().hi} : Interval{Interval::full().lo, t};
}

Interval LinearSweep::generic_chord(const Ray& ray) const {
  const Vec3 o = tcs_.to_local(ray.origin);
  const Vec3 d = tcs_.direction_to_local(ray.direction);
  Hull hull;
  // The tool at the start and at the end (a convex tool: the hull of its pieces' chords).
  for (const Ray& at_end : {Ray{o, d}, Ray{o - delta_, d}}) {
    for (const ProfileSegment& s : cutter_->profile().segments())
      hull.add(convex_piece_chord(s, at_end));
  }

  const Vec3 n = d.cross(delta_);
  if (n.norm() <= tol::kAngle * d.norm() * delta_.norm()) {
    // The ray runs along the feed (or the move is empty): the two tool chords bound the chord.
    return hull.interval();
  }
  // A point p of the tool (at the start) swept along D: where the ray meets its path, if it does
  // (p must lie in the plane of the ray and D, within rounding of the model's size).
  const double scale = o.norm() + delta_.norm() + cutter_->bounding_cylinder().z_max;
  const auto add_point = [&](const Vec3& p) {
    double t = 0.0, lambda = 0.0;
    if (!solve_in_plane(d, delta_, p - o, t, lambda) || lambda < 0.0 || lambda > 1.0) return;
    if ((o + t * d - p - lambda * delta_).norm() >
        tol::kLength * (1.0 + scale / tol::kModelScale)) {
      return;
    }
    hull.add(t);
  };
  const double offset = n.dot(o);

  // Swept vertex circles (profile vertices: tip, joints, top edge).
  for (const Vec2& v : vertices_) {
    if (v.x() <= 0.0) {
      add_point(Vec3(0.0, 0.0, v.y()));  // a point on the axis: its swept segment
      continue;
    }
    // n·(ρ sin φ, ρ cos φ, z) = n·o: the line a·s + b·c = k meets the unit circle (s, c) at
    // the foot of the perpendicular ± h along the line (no trigonometry needed).
    const double a = n.x() * v.x(), b = n.y() * v.x(), k = offset - n.z() * v.y();
    const double r2 = a * a + b * b;
    if (!(r2 > 0.0)) continue;
    const double h2 = 1.0 - k * k / r2;
    if (h2 < 0.0) continue;
    const double h = std::sqrt(h2 / r2);
    const double s0 = a * k / r2, c0 = b * k / r2;
    for (const double sign : {-1.0, 1.0}) {
      add_point(Vec3(v.x() * (s0 - sign * b * h), v.x() * (c0 + sign * a * h), v.y()));
    }
  }
  if (lateral_ <= tol::kLength) return hull.interval();  // axial motion: vertex circles suffice

  // Swept grazing generators of line pieces: a straight generator at a constant φ sweeps a plane
  // that meets the ray where g(u) = n·(G(u) - o) changes sign, and g is linear in u.
  for (const Generator& generator : generators_) {
    const double g0 = n.dot(generator.a) - offset, g1 = n.dot(generator.b) - offset;
    if ((g0 > 0.0) == (g1 > 0.0) && g0 != 0.0 && g1 != 0.0) continue;
    const double u = std::clamp(g0 == g1 ? 0.0 : g0 / (g0 - g1), 0.0, 1.0);
    add_point(generator.a + u * (generator.b - generator.a));
  }
  // Swept great circles of spheres: the cylinder of radius r about the centre's path, where the
  // grazing point lies on the sphere's piece of the profile.
  for (const SpherePiece& sphere : spheres_) {
    const Vec3 rel = o - Vec3(0.0, 0.0, sphere.center_z);
    swept_ball_side(rel, d, delta_, sphere.radius, [&](double t, double along) {
      const double lambda = along / delta_.squaredNorm();
      const double height = sphere.center_z + (rel + t * d - lambda * delta_).z();
      if (height >= sphere.z0 && height <= sphere.z1) hull.add(t);
    });
  }
  // Swept grazing curves of arcs: sign changes of the crossing function between samples,
  // refined by Brent's method; a root counts only where the grazing angle exists.
  for (const GrazingSamples& arc : arcs_) {
    const auto g = [&](double u) {
      bool exists = false;
      return n.dot(grazing_point(arc.segment, arc.branch, u, exists)) - offset;
    };
    const auto add_root = [&](double u) {
      bool exists = false;
      const Vec3 p = grazing_point(arc.segment, arc.branch, u, exists);
      if (exists) add_point(p);
    };
    double g_prev = n.dot(arc.point[0]) - offset;
    if (g_prev == 0.0 && arc.exists[0]) add_point(arc.point[0]);
    for (int k = 1; k <= kArcSamples; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const double gu = n.dot(arc.point[kk]) - offset;
      if (gu == 0.0) {
        if (arc.exists[kk]) add_point(arc.point[kk]);
      } else if (g_prev != 0.0 && (gu > 0.0) != (g_prev > 0.0) && !arc.none_between[kk]) {
        if (const auto root = brent_root(g, static_cast<double>(k - 1) / kArcSamples,
                                         static_cast<double>(k) / kArcSamples)) {
          add_root(*root);
        }
      }
      g_prev = gu;
    }
  }
  return hull.interval();
}

}  // namespace cwe
