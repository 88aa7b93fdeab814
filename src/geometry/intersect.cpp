#include "cwe/geometry/intersect.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "cwe/core/assert.hpp"
#include "cwe/geometry/roots.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "polynomial.hpp"

namespace cwe {

namespace {

// Axes and normals are unit vectors; |v|² - 1 ≈ 2(|v| - 1), an angle-sized error at most.
[[maybe_unused]] bool is_unit(const Vec3& v) {
  return std::abs(v.squaredNorm() - 1.0) <= tol::kAngle;
}

Interval full_or_empty(bool inside) { return inside ? Interval::full() : Interval::empty(); }

// The parameters x with s0 + x·ds in [lo, hi] (lo or hi may be infinite).
Interval slab(double s0, double ds, double lo, double hi) {
  if (ds == 0.0) {
    // Moving parallel to the slab: all or nothing, by the side of the start.
    return full_or_empty(s0 >= lo && s0 <= hi);
  }
  double a = (lo - s0) / ds;
  double b = (hi - s0) / ds;
  if (a > b) std::swap(a, b);
  // For a tiny ds both ends can overflow to the same infinity: the crossing lies beyond the range
  // of doubles, on the far side of the start, so the slab is never reached.
  if (a == b && std::isinf(a)) return Interval::empty();
  return {a, b};
}

// A ray re-expressed with a unit direction and its origin moved to the point of the line closest
// to a reference point (the primitive's centre): the coefficients of the intersection polynomials
// then stay of the primitive's size, free of the cancellation a distant origin would cause.
// Points are P(x) = reference + offset + x·direction, and ray parameters t = (shift + x) / length.
struct LocalRay {
  Vec3 offset;     // closest point of the line, relative to the reference point
  Vec3 direction;  // unit
  double length = 0.0;
  double shift = 0.0;

  double ray_parameter(double x) const { return (shift + x) / length; }
  Interval ray_interval(const Interval& x) const {
    if (x.is_empty()) return Interval::empty();
    return {ray_parameter(x.lo), ray_parameter(x.hi)};
  }
};

// Requires a non-zero ray direction (callers branch on the zero direction first).
LocalRay local_ray(const Ray& ray, const Vec3& reference, double length) {
  LocalRay local;
  local.length = length;
  local.direction = ray.direction / length;
  const Vec3 relative = ray.origin - reference;
  local.shift = -relative.dot(local.direction);
  local.offset = relative + local.shift * local.direction;
  return local;
}

// The x with |offset + x·direction| ≤ radius, for a unit direction (a chord of a ball, or of a
// circle when both lie in a plane). `position_scale` is the size of the coordinates the offset
// was computed from: its rounding is what makes a tangency uncertain.
Interval ball_chord(const Vec3& offset, const Vec3& direction, double radius,
                    double position_scale) {
  // The offset is the closest point up to rounding; take its remaining along-ray part out.
  const double along = offset.dot(direction);
  const double distance = (offset - along * direction).norm();
  // r² - d² as a product, without cancellation.
  const double half_chord_squared = (radius - distance) * (radius + distance);
  // Tangent within rounding: the error of d² is about 2d·(rounding of the offset).
  const double allowance =
      tol::kGeometricRounding * (radius + distance) * (radius + position_scale);
  if (half_chord_squared < -allowance) return Interval::empty();        // the line misses
  if (half_chord_squared <= allowance) return Interval::point(-along);  // tangent: [x, x]
  const double half_chord = std::sqrt(half_chord_squared);
  return {-along - half_chord, -along + half_chord};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Implicit functions and membership (Aras 2008, eq. 6.7: negative inside).

double implicit_value(const Plane& plane, const Vec3& p) {
  return (p - plane.point).dot(plane.normal);
}

double implicit_value(const Sphere& sphere, const Vec3& p) {
  return (p - sphere.center).squaredNorm() - sphere.radius * sphere.radius;
}

namespace {

// Radius of the frustum at height s, the linear profile extended beyond [0, height]. A frustum
// of zero height is the flat disc of the larger radius (the hull of its two end circles).
double frustum_radius(const Frustum& frustum, double s) {
  if (frustum.height == 0.0) return std::max(frustum.radius0, frustum.radius1);
  return frustum.radius0 + (frustum.radius1 - frustum.radius0) * (s / frustum.height);
}

double tube_value(const Torus& torus, const Vec3& p) {
  const Vec3 relative = p - torus.center;
  const double z = relative.dot(torus.axis);
  const double rho = (relative - z * torus.axis).norm();
  const double radial = rho - torus.major_radius;
  return radial * radial + z * z - torus.minor_radius * torus.minor_radius;
}

}  // namespace

double implicit_value(const Frustum& frustum, const Vec3& p) {
  const Vec3 relative = p - frustum.base;
  const double s = relative.dot(frustum.axis);
  const double radius = frustum_radius(frustum, s);
  return (relative - s * frustum.axis).squaredNorm() - radius * radius;
}

double implicit_value(const Torus& torus, const Vec3& p) {
  const Vec3 relative = p - torus.center;
  const double squared = relative.squaredNorm();
  const double z = relative.dot(torus.axis);
  const double major_squared = torus.major_radius * torus.major_radius;
  const double first = squared + major_squared - torus.minor_radius * torus.minor_radius;
  return first * first - 4.0 * major_squared * (squared - z * z);
}

bool contains(const Sphere& sphere, const Vec3& p) { return implicit_value(sphere, p) <= 0.0; }

bool contains(const Frustum& frustum, const Vec3& p) {
  const Vec3 relative = p - frustum.base;
  const double s = relative.dot(frustum.axis);
  if (s < 0.0 || s > frustum.height) return false;
  const double radius = frustum_radius(frustum, s);
  return (relative - s * frustum.axis).squaredNorm() <= radius * radius;
}

bool contains(const Torus& torus, const Vec3& p) { return tube_value(torus, p) <= 0.0; }

// ---------------------------------------------------------------------------------------------
// Planes and discs.

Interval intersect(const Ray& ray, const Plane& halfspace) {
  CWE_ASSERT(is_unit(halfspace.normal), "plane normal must be a unit vector");
  const double start = implicit_value(halfspace, ray.origin);  // (o - B)·n
  const double rate = ray.direction.dot(halfspace.normal);     // d·n
  if (rate == 0.0) {
    // Parallel ray (or zero direction): the whole line is on the side of its origin.
    return full_or_empty(start <= 0.0);
  }
  const double crossing = -start / rate;
  if (!std::isfinite(crossing)) {
    // Nearly parallel: the crossing lies beyond the range of doubles, so every representable
    // parameter is on the side of the origin.
    return full_or_empty(start <= 0.0);
  }
  return rate > 0.0 ? Interval{-std::numeric_limits<double>::infinity(), crossing}
                    : Interval{crossing, std::numeric_limits<double>::infinity()};
}

Interval intersect_surface(const Ray& ray, const Plane& plane) {
  CWE_ASSERT(is_unit(plane.normal), "plane normal must be a unit vector");
  const double start = implicit_value(plane, ray.origin);
  const double rate = ray.direction.dot(plane.normal);
  if (std::abs(rate) <= tol::kAngle * ray.direction.norm() && std::abs(start) <= tol::kLength) {
    // The ray lies in the plane: within kLength at the origin and drifting by at most
    // kAngle·|t·d|, i.e. within kLength over a model-sized (kLength / kAngle = 1 m) stretch.
    return Interval::full();
  }
  if (rate == 0.0) return Interval::empty();  // parallel, off the plane
  const double crossing = -start / rate;
  if (!std::isfinite(crossing)) return Interval::empty();  // beyond the range of doubles
  return Interval::point(crossing);
}

Interval intersect(const Ray& ray, const Disc& disc) {
  CWE_ASSERT(is_unit(disc.normal), "disc normal must be a unit vector");
  CWE_ASSERT(disc.radius >= 0.0, "disc radius must be non-negative");
  const Vec3 relative = ray.origin - disc.center;
  const double start = relative.dot(disc.normal);
  const double rate = ray.direction.dot(disc.normal);
  const double length = ray.direction.norm();
  if (std::abs(rate) <= tol::kAngle * length && std::abs(start) <= tol::kLength) {
    // Coplanar ray (as in intersect_surface): the chord of the disc's circle, solved in the
    // plane. A zero direction lands here too and is tested as a point.
    const Vec3 in_plane_origin = relative - start * disc.normal;
    const Vec3 in_plane_direction = ray.direction - rate * disc.normal;
    const double in_plane_length = in_plane_direction.norm();
    if (in_plane_length == 0.0) return full_or_empty(in_plane_origin.norm() <= disc.radius);
    const LocalRay local =
        local_ray(Ray{in_plane_origin, in_plane_direction}, Vec3::Zero(), in_plane_length);
    const double position_scale = ray.origin.norm() + disc.center.norm();
    return local.ray_interval(
        ball_chord(local.offset, local.direction, disc.radius, position_scale));
  }
  if (rate == 0.0) return Interval::empty();  // parallel, off the plane
  const double crossing = -start / rate;
  if (!std::isfinite(crossing)) return Interval::empty();  // beyond the range of doubles
  const Vec3 hit = relative + crossing * ray.direction;
  if (hit.squaredNorm() > disc.radius * disc.radius) return Interval::empty();
  return Interval::point(crossing);
}

// ---------------------------------------------------------------------------------------------
// Sphere.

Interval intersect(const Ray& ray, const Sphere& sphere) {
  CWE_ASSERT(sphere.radius >= 0.0, "sphere radius must be non-negative");
  const double length = ray.direction.norm();
  if (length == 0.0) {
    // Zero direction (or one whose squared length underflows): the ray is its origin.
    return full_or_empty(contains(sphere, ray.origin));
  }
  const LocalRay local = local_ray(ray, sphere.center, length);
  const double position_scale = ray.origin.norm() + sphere.center.norm();
  return local.ray_interval(
      ball_chord(local.offset, local.direction, sphere.radius, position_scale));
}

// ---------------------------------------------------------------------------------------------
// Frustum.

Interval intersect(const Ray& ray, const Frustum& frustum) {
  CWE_ASSERT(is_unit(frustum.axis), "frustum axis must be a unit vector");
  CWE_ASSERT(frustum.radius0 >= 0.0 && frustum.radius1 >= 0.0 && frustum.height >= 0.0,
             "frustum radii and height must be non-negative");
  const double height = frustum.height;
  if (height == 0.0) {
    // Zero height: the flat disc of the larger radius.
    return intersect(ray,
                     Disc{frustum.base, frustum.axis, std::max(frustum.radius0, frustum.radius1)});
  }
  const double length = ray.direction.norm();
  if (length == 0.0) return full_or_empty(contains(frustum, ray.origin));  // zero direction

  const Vec3& axis = frustum.axis;
  const Vec3 middle = frustum.base + (0.5 * height) * axis;
  const LocalRay local = local_ray(ray, middle, length);
  // Local coordinates from the base: height s and radial vector, at x = 0 and per unit x.
  const Vec3 start = local.offset + (0.5 * height) * axis;
  const double s0 = start.dot(axis);
  const Vec3 radial0 = start - s0 * axis;
  const double ds = local.direction.dot(axis);
  const Vec3 radial_rate = local.direction - ds * axis;
  // The size of the coordinates the local values were computed from (their rounding).
  const double position_scale = ray.origin.norm() + frustum.base.norm() + height;

  // The height slab, and the same widened by rounding: when the exact slab misses the lateral
  // solution, a contact within rounding of an end face (a grazing ray) or of the apex of a cone
  // is kept from the widened one, as a tangent contact is never lost to rounding. Only then, so
  // that ordinary chords end exactly on the faces.
  const double slab_allowance = tol::kGeometricRounding * position_scale;
  const Interval height_range = slab(s0, ds, 0.0, height);
  const Interval widened_height_range = slab(s0, ds, -slab_allowance, height + slab_allowance);
  if (widened_height_range.is_empty()) return Interval::empty();

  const double slope = (frustum.radius1 - frustum.radius0) / height;  // dr/ds
  const double radial_rate_length = radial_rate.norm();
  constexpr double kInfinity = std::numeric_limits<double>::infinity();

  if (radial_rate_length <= tol::kAngle) {
    // Ray parallel to the axis: its distance rho from the axis is constant (to kAngle·height);
    // take it at mid-height. Inside where r(s) ≥ rho: the whole slab for a cylinder within
    // the radius; for a varying radius the ray enters (or leaves) through the side at
    // s = (rho - r0) / slope.
    const double x_middle = (0.5 * height - s0) / ds;  // |ds| ≈ 1 here
    const double rho = (radial0 + x_middle * radial_rate).norm();
    // Heights where r(s) ≥ rho - allowance, as ray parameters.
    const auto inside_radius = [&](double allowance) {
      if (slope == 0.0) return full_or_empty(rho - allowance <= frustum.radius0);
      const double edge = (rho - allowance - frustum.radius0) / slope;
      return slab(s0, ds, slope > 0.0 ? edge : -kInfinity, slope > 0.0 ? kInfinity : edge);
    };
    const Interval exact = intersect(height_range, inside_radius(0.0));
    if (!exact.is_empty()) return local.ray_interval(exact);
    // A ray on the wall, or grazing a face, within rounding.
    const double radius_allowance = tol::kGeometricRounding * (rho + position_scale);
    return local.ray_interval(intersect(widened_height_range, inside_radius(radius_allowance)));
  }

  // General position: |radial(x)|² - r(s(x))² ≤ 0 is A x² + B x + C ≤ 0 (the double cone, or
  // the infinite cylinder); within the slab r ≥ 0, so that is exactly |radial| ≤ r.
  const double radius_start = frustum.radius0 + slope * s0;
  const double slope_rate = slope * ds;
  const double a = radial_rate.squaredNorm() - slope_rate * slope_rate;
  const double b = 2.0 * (radial0.dot(radial_rate) - slope_rate * radius_start);
  const double c = radial0.squaredNorm() - radius_start * radius_start;
  // Error bounds of the coefficients: lengths in them carry the rounding of the coordinates
  // (position_scale, amplified by the slope through r(s)) and of their own few operations.
  const double local_size = radial0.norm() + std::abs(radius_start);
  const double error_size = local_size + (1.0 + std::abs(slope)) * position_scale;
  detail::Polynomial quadratic;
  quadratic.degree = 2;
  quadratic.coefficient = {a, b, c, 0.0, 0.0};
  quadratic.error = {
      tol::kGeometricRounding * (radial_rate.squaredNorm() + slope_rate * slope_rate),
      tol::kGeometricRounding * 2.0 * (radial_rate_length + std::abs(slope_rate)) * error_size,
      tol::kGeometricRounding * local_size * error_size, 0.0, 0.0};
  const Roots roots = detail::solve(quadratic);

  // The solution set of the inequality: one or two pieces.
  Interval first = Interval::empty();
  Interval second = Interval::empty();
  if (roots.identically_zero) {
    // A = B = C = 0: the line runs on the cone's surface (a generator).
    first = Interval::full();
  } else if (roots.empty()) {
    // No real root (or none within kRootSearchLimit): Q has one sign on every parameter a double
    // can hold, the sign it has at x = 0.
    first = full_or_empty(c <= 0.0);
  } else if (roots.size() == 1 && roots.tangent[0]) {
    // Tangent (double root): shallower than the cone (A > 0), the line touches the surface,
    // [x, x]; steeper (A < 0), it lies inside the double cone, touching at the apex.
    first = a > 0.0 ? Interval::point(roots[0]) : Interval::full();
  } else if (roots.size() == 1) {
    // One simple root: A = 0 (the ray is parallel to a generator, Q is linear), or the other root
    // lies beyond kRootSearchLimit (A within rounding of 0). Q ≤ 0 on the side where it falls.
    const double slope_at_root = 2.0 * a * roots[0] + b;
    if (slope_at_root > 0.0) {
      first = {-kInfinity, roots[0]};
    } else if (slope_at_root < 0.0) {
      first = {roots[0], kInfinity};
    } else {
      first = Interval::point(roots[0]);  // flat at a simple root only by rounding: the root
    }
  } else if (a > 0.0) {
    // Shallower than the cone (or any direction, for a cylinder): between the roots.
    first = {roots[0], roots[1]};
  } else {
    // Steeper than the cone: outside the roots, one piece in each nappe.
    first = {-kInfinity, roots[0]};
    second = {roots[1], kInfinity};
  }
  // The solid is convex, so in exact arithmetic at most one piece meets the slab (the other
  // nappe lies beyond the apex); rounding at the apex can leave a sliver of the other: the hull
  // absorbs it.
  const auto within = [&](const Interval& range) {
    return hull(intersect(first, range), intersect(second, range));
  };
  const Interval exact = within(height_range);
  if (!exact.is_empty()) return local.ray_interval(exact);
  return local.ray_interval(within(widened_height_range));  // grazing a face, or the apex
}

// ---------------------------------------------------------------------------------------------
// Torus.

IntervalPair intersect(const Ray& ray, const Torus& torus) {
  CWE_ASSERT(is_unit(torus.axis), "torus axis must be a unit vector");
  CWE_ASSERT(torus.major_radius >= 0.0 && torus.minor_radius >= 0.0,
             "torus radii must be non-negative");
  IntervalPair result;
  const auto add = [&result](const Interval& interval) {
    if (interval.is_empty()) return;
    result.interval[static_cast<std::size_t>(result.count++)] = interval;
  };
  const double length = ray.direction.norm();
  if (length == 0.0) {
    add(full_or_empty(contains(torus, ray.origin)));  // zero direction
    return result;
  }
  if (torus.major_radius == 0.0) {
    // Major radius 0: the tube about a point is the ball of the minor radius (the quartic would
    // be the square of the sphere's quadratic, all its roots double).
    add(intersect(ray, Sphere{torus.center, torus.minor_radius}));
    return result;
  }

  const double major = torus.major_radius;
  const double minor = torus.minor_radius;
  const Vec3& axis = torus.axis;
  const LocalRay local = local_ray(ray, torus.center, length);
  const Vec3& p = local.offset;
  const Vec3& u = local.direction;
  // P(x) = p + x u relative to the centre; z and the radial vector per unit x.
  const double uu = u.squaredNorm();
  const double beta = p.dot(u);
  const double pz = p.dot(axis);
  const double uz = u.dot(axis);
  const Vec3 radial0 = p - pz * axis;
  const Vec3 radial_rate = u - uz * axis;
  const double major_squared = major * major;
  // Rays along the axis or square to it (every axis-aligned dexel ray of a tool standing along a
  // world axis) meet the tube in closed form: a vertical line at constant ρ, or a line in a
  // plane z = const across the annulus R ± √(r² - z²).
  // A tangency (a zero under the root) is kept as a touching point within the rounding of the
  // coordinates, as the quartic path does.
  constexpr double kAligned = 1e-14;
  const double allowance = 4.0 * tol::kGeometricRounding * (major + minor) *
                           (p.norm() + major + minor + ray.origin.norm() + torus.center.norm());
  if (radial_rate.squaredNorm() <= kAligned * kAligned) {
    const double rho = radial0.norm();
    const double w2 = minor * minor - (rho - major) * (rho - major);
    if (w2 < -allowance) return result;
    const double w = w2 <= allowance ? 0.0 : std::sqrt(w2);
    const double a = (-w - pz) / uz, b = (w - pz) / uz;
    add(local.ray_interval({std::min(a, b), std::max(a, b)}));
    return result;
  }
  if (std::abs(uz) <= kAligned) {
    const double h2 = minor * minor - pz * pz;
    if (h2 < -allowance) return result;
    const double h = h2 <= allowance ? 0.0 : std::sqrt(h2);
    // The line's closest point to the axis is the offset's radial part (u ⟂ axis, p ⟂ u).
    const double d2 = radial0.squaredNorm();
    const double outer = major + h, inner = major - h;
    if (outer * outer < d2) return result;
    const double a = std::sqrt(outer * outer - d2);
    if (inner > 0.0 && inner * inner > d2) {
      const double c = std::sqrt(inner * inner - d2);
      add(local.ray_interval({-a, -c}));
      add(local.ray_interval({c, a}));
    } else {
      add(local.ray_interval({-a, a}));
    }
    return result;
  }
  const double e = p.squaredNorm() + major_squared - minor * minor;
  // (|P|² + R² - r²)² - 4R²|P_radial|² with |P|² = uu x² + 2βx + |p|² (Aras 2008 uses the same
  // implicit form, eq. 6.7).
  detail::Polynomial quartic;
  quartic.degree = 4;
  quartic.coefficient = {
      uu * uu, 4.0 * uu * beta,
      4.0 * beta * beta + 2.0 * uu * e - 4.0 * major_squared * radial_rate.squaredNorm(),
      4.0 * beta * e - 8.0 * major_squared * radial0.dot(radial_rate),
      e * e - 4.0 * major_squared * radial0.squaredNorm()};
  // Coefficient i has the dimension length^i and is a sum of a few products of local lengths
  // (size ≤ local_size) whose rounding is that of the coordinates (size ≤ error_size).
  const double local_size = p.norm() + major + minor;
  const double error_size = local_size + ray.origin.norm() + torus.center.norm();
  double power = error_size / local_size;
  for (std::size_t i = 0; i < 5; ++i) {
    quartic.error[i] = tol::kGeometricRounding * power;
    power *= local_size;
  }
  const Roots roots = detail::solve(quartic);
  const int count = roots.size();
  if (count == 0) return result;

  // Candidate boundaries are the real roots (the tube's crossings, and for a spindle torus also
  // the crossings of its inner lemon, which the quartic contains too). Membership of each
  // stretch between candidates is decided by the tube test at its midpoint.
  const auto tube = [&](double x) {
    const double rho = (radial0 + x * radial_rate).norm();
    const double z = pz + x * uz;
    return (rho - major) * (rho - major) + z * z - minor * minor;
  };
  std::array<double, 3> middle{};
  std::array<bool, 3> inside{};
  for (int i = 0; i + 1 < count; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    middle[k] = 0.5 * (roots[i] + roots[i + 1]);
    inside[k] = tube(middle[k]) <= 0.0;
  }
  // Before the first and after the last candidate the line is outside; `span` reaches a point
  // there for polishing.
  const double span = major + minor;
  struct Piece {
    double lo;
    double hi;
  };
  std::vector<Piece> pieces;
  std::array<bool, 4> covered{};
  const auto polish = [&](double candidate, double outside_point, double inside_point) {
    // Brent on the tube function between an outside and an inside point, both straddling the
    // candidate: the tube function is better conditioned than the quartic (its square-like
    // product with the other factor). Keeps the candidate if the signs do not bracket.
    if (!(tube(inside_point) < 0.0) || !(tube(outside_point) > 0.0)) return candidate;
    const double lo = std::min(outside_point, inside_point);
    const double hi = std::max(outside_point, inside_point);
    return brent_root(tube, lo, hi).value_or(candidate);
  };
  for (int i = 0; i + 1 < count;) {
    if (!inside[static_cast<std::size_t>(i)]) {
      ++i;
      continue;
    }
    const int first = i;
    while (i + 1 < count && inside[static_cast<std::size_t>(i)]) ++i;
    const int last = i;  // candidates first..last bound inside stretches
    for (int j = first; j <= last; ++j) covered[static_cast<std::size_t>(j)] = true;
    const std::size_t f = static_cast<std::size_t>(first);
    const std::size_t l = static_cast<std::size_t>(last);
    const double lo_outside = first == 0 ? roots[0] - span : middle[f - 1];
    const double hi_outside = last == count - 1 ? roots[count - 1] + span : middle[l];
    pieces.push_back({polish(roots[first], lo_outside, middle[f]),
                      polish(roots[last], hi_outside, middle[l - 1])});
  }
  for (int i = 0; i < count; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (covered[k]) continue;
    // A candidate alone: a tangent (double) root touches the tube, [x, x]. A lone simple root
    // is a crossing whose neighbouring stretch rounding made too thin to test: keep it only if
    // it is in the tube.
    if (roots.tangent[k] || tube(roots[i]) <= 0.0) pieces.push_back({roots[i], roots[i]});
  }
  std::sort(pieces.begin(), pieces.end(),
            [](const Piece& a, const Piece& b) { return a.lo < b.lo; });
  // A line meets a torus in at most four points, so at most two pieces; should rounding produce
  // more, merge across the smallest gaps.
  while (pieces.size() > 2) {
    std::size_t best = 0;
    for (std::size_t k = 1; k + 1 < pieces.size(); ++k) {
      if (pieces[k + 1].lo - pieces[k].hi < pieces[best + 1].lo - pieces[best].hi) best = k;
    }
    pieces[best].hi = std::max(pieces[best].hi, pieces[best + 1].hi);
    pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(best) + 1);
  }
  for (const Piece& piece : pieces) {
    add(local.ray_interval(Interval{piece.lo, std::max(piece.lo, piece.hi)}));
  }
  return result;
}

}  // namespace cwe
