#include "cwe/envelope/linear_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cwe/core/error.hpp"
#include "cwe/envelope/swept_volume.hpp"
#include "cwe/geometry/roots.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {
namespace {

// Samples of an arc's angle range when looking for crossings of its swept grazing curve. The
// crossing function has at most a few extrema over a quarter circle; 24 samples bracket every
// transversal crossing, and a tangent touch that falls between samples only loses a degenerate
// point of the chord, which the neighbouring surfaces then supply.
constexpr int kArcSamples = 24;

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

}  // namespace

LinearSweep::LinearSweep(const Cutter& cutter, const Vec3& start, const Vec3& end, const Vec3& axis)
    : cutter_(&cutter) {
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
}

Interval LinearSweep::chord(const Ray& ray) const {
  const Cutter& cutter = *cutter_;
  const Vec3 o = tcs_.to_local(ray.origin);
  const Vec3 d = tcs_.direction_to_local(ray.direction);
  Hull hull;
  // The tool at the start and at the end.
  for (const Interval& i : cutter.intersect(Ray{o, d})) hull.add(i);
  for (const Interval& i : cutter.intersect(Ray{o - delta_, d})) hull.add(i);

  const Vec3 n = d.cross(delta_);
  if (n.norm() <= tol::kAngle * d.norm() * delta_.norm()) {
    // The ray runs along the feed (or the move is empty): the two tool chords bound the chord.
    return hull.lo <= hull.hi ? Interval{hull.lo, hull.hi} : Interval::empty();
  }
  // A point p of the tool (at the start) swept along D: where the ray meets its path, if it does
  // (p must lie in the plane of the ray and D, within rounding of the model's size).
  const double scale = o.norm() + delta_.norm() + cutter.bounding_cylinder().z_max;
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
  const auto& segments = cutter.profile().segments();
  std::vector<Vec2> vertices{segments.front().start};
  for (const auto& s : segments) vertices.push_back(s.end);
  for (const Vec2& v : vertices) {
    if (v.x() <= 0.0) {
      add_point(Vec3(0.0, 0.0, v.y()));  // a point on the axis: its swept segment
      continue;
    }
    // n·(ρ sin φ, ρ cos φ, z) = n·o
    const Roots roots = solve_sin_cos(n.x() * v.x(), n.y() * v.x(), n.z() * v.y() - offset);
    for (const double phi : roots)
      add_point(Vec3(v.x() * std::sin(phi), v.x() * std::cos(phi), v.y()));
  }

  // Swept grazing curves of the smooth patches: N·D = n_ρ (D_x sin φ + D_y cos φ) + n_z D_z = 0.
  const double dx = delta_.x(), dy = delta_.y(), dz = delta_.z();
  const double lateral = std::hypot(dx, dy);
  if (lateral <= tol::kLength) return {hull.lo, hull.hi};  // axial motion: vertex circles suffice
  const double phase = std::atan2(dy, dx);  // D_x sin φ + D_y cos φ = L sin(φ + phase)
  // The grazing angles of profile point (ρ, z) with normal (n_ρ, n_z), or false.
  // With `clamp`, sin φ is clamped into [-1, 1] (a continuous extension for root bracketing)
  // and the result says whether clamping was needed.
  const auto grazing = [&](const Vec2& normal, int branch, double& phi, bool clamp = false) {
    if (std::abs(normal.x()) <= tol::kAngle) return false;  // horizontal faces have none
    double s = -normal.y() * dz / (normal.x() * lateral);
    const bool inside = s >= -1.0 && s <= 1.0;
    if (!inside && !clamp) return false;
    s = std::clamp(s, -1.0, 1.0);
    const double base = std::asin(s);
    phi = (branch == 0 ? base : kPi - base) - phase;
    return inside;
  };
  for (const auto& segment : segments) {
    if (segment.kind == ProfileSegment::Kind::kLine) {
      // A straight generator at a constant φ: its swept plane meets the ray where
      // g(u) = n·(G(u) - o) changes sign, and g is linear in u.
      const Vec2 normal = segment.normal_at(0.0);
      for (int branch = 0; branch < 2; ++branch) {
        double phi = 0.0;
        if (!grazing(normal, branch, phi)) continue;
        const auto at = [&](double u) {
          const Vec2 p = segment.point_at(u);
          return Vec3(p.x() * std::sin(phi), p.x() * std::cos(phi), p.y());
        };
        const double g0 = n.dot(at(0.0)) - offset, g1 = n.dot(at(1.0)) - offset;
        if ((g0 > 0.0) == (g1 > 0.0) && g0 != 0.0 && g1 != 0.0) continue;
        const double u = g0 == g1 ? 0.0 : g0 / (g0 - g1);
        add_point(at(std::clamp(u, 0.0, 1.0)));
      }
      continue;
    }
    // An arc: sample the crossing function along it, refine sign changes. Where no grazing
    // angle exists (|sin φ| would exceed 1) the function is continued with sin φ clamped, so
    // that crossings near the end of the grazing curve are still bracketed; a root counts only
    // where the grazing angle exists.
    for (int branch = 0; branch < 2; ++branch) {
      const auto point_at = [&](double u, bool& exists) {
        double phi = 0.0;
        exists = grazing(segment.normal_at(u), branch, phi, true);
        const Vec2 p = segment.point_at(u);
        return Vec3(p.x() * std::sin(phi), p.x() * std::cos(phi), p.y());
      };
      const auto g = [&](double u) {
        bool exists = false;
        return n.dot(point_at(u, exists)) - offset;
      };
      const auto add_root = [&](double u) {
        bool exists = false;
        const Vec3 p = point_at(u, exists);
        if (exists) add_point(p);
      };
      double u_prev = 0.0;
      double g_prev = g(0.0);
      if (g_prev == 0.0) add_root(0.0);
      for (int k = 1; k <= kArcSamples; ++k) {
        const double u = static_cast<double>(k) / kArcSamples;
        const double gu = g(u);
        if (gu == 0.0) {
          add_root(u);
        } else if (g_prev != 0.0 && (gu > 0.0) != (g_prev > 0.0)) {
          if (const auto root = brent_root(g, u_prev, u)) add_root(*root);
        }
        u_prev = u;
        g_prev = gu;
      }
    }
  }
  return hull.lo <= hull.hi ? Interval{hull.lo, hull.hi} : Interval::empty();
}

}  // namespace cwe
