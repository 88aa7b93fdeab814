#pragma once
// Ray ∩ primitive, as the interval of ray parameters t for which ray.at(t) lies in the closed
// primitive. Solids give the chord inside them; surfaces (plane, disc) give the degenerate
// interval [t, t] of the crossing, or a chord when the ray lies in them.
//
// Degenerate cases are explicit, each named in the function's comment:
//  - ray parallel to a plane, or to a cylinder's or cone's axis;
//  - ray tangent to a surface: a degenerate interval [t, t] (never lost to rounding: a
//    discriminant within rounding of zero counts as tangent);
//  - ray origin inside the primitive: the interval simply contains 0;
//  - zero direction: the interval is full when the origin is inside, empty otherwise.
// Axes and normals must be unit vectors (CWE_ASSERT); ray directions need not be.
//
// The implicit functions are the forms of Aras 2008, eq. 6.7 (negative inside, zero on the
// surface, positive outside); brute-force tests use them as oracles.

#include <array>

#include "cwe/geometry/interval.hpp"
#include "cwe/geometry/ray.hpp"
#include "cwe/geometry/vec.hpp"

namespace cwe {

// Up to two disjoint intervals, ascending (the solid torus).
struct IntervalPair {
  std::array<Interval, 2> interval{Interval::empty(), Interval::empty()};
  int count = 0;
  const Interval* begin() const { return interval.data(); }
  const Interval* end() const { return interval.data() + count; }
  bool empty() const { return count == 0; }
};

// Plane through `point` with unit `normal`.
struct Plane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
};

// Ball of centre `center` and `radius`.
struct Sphere {
  Vec3 center = Vec3::Zero();
  double radius = 1.0;
};

// Solid truncated cone (frustum) along unit `axis` from `base`: heights s = (P - base)·axis in
// [0, height], radius varying linearly from `radius0` at s = 0 to `radius1` at s = height.
// Covers the finite cylinder (radius0 == radius1) and the one-nappe cone (radius0 == 0, apex at
// base). Both radii ≥ 0, height ≥ 0.
struct Frustum {
  Vec3 base = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
  double radius0 = 1.0;
  double radius1 = 1.0;
  double height = 1.0;
};

// Flat disc of `radius` centred at `center` with unit `normal`.
struct Disc {
  Vec3 center = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  double radius = 1.0;
};

// Solid torus (tube): points within `minor_radius` of the circle of `major_radius` about unit
// `axis` through `center`. major_radius ≥ 0 (0 is a ball); a spindle torus
// (major < minor) is the tube, i.e. its inner lemon counts as inside.
struct Torus {
  Vec3 center = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
  double major_radius = 2.0;
  double minor_radius = 1.0;
};

// Signed implicit values (negative inside).
double implicit_value(const Plane& plane, const Vec3& p);  // (p - B)·n
double implicit_value(const Sphere& sphere, const Vec3& p);  // |p - C|² - r²
// Finite cylinder (radius0 == radius1): |p - B|² - ((p - B)·n)² - r², ignoring the height.
// Cone: |radial|² - r(s)², with r(s) the linear radius extended beyond [0, height].
double implicit_value(const Frustum& frustum, const Vec3& p);
// (|p - C|² + R² - r²)² - 4R²(|p - C|² - ((p - C)·n)²)
double implicit_value(const Torus& torus, const Vec3& p);

// Closed membership tests of the solids (height limits included for the frustum).
bool contains(const Sphere& sphere, const Vec3& p);
bool contains(const Frustum& frustum, const Vec3& p);
bool contains(const Torus& torus, const Vec3& p);

// Half-space (p - B)·n ≤ 0. Parallel ray: full or empty by the side of the origin.
Interval intersect(const Ray& ray, const Plane& halfspace);

// The plane itself: [t, t] at the crossing; parallel ray: full when in the plane (within
// tol::kLength), else empty.
Interval intersect_surface(const Ray& ray, const Plane& plane);

// The disc: [t, t] at the crossing when within the radius; a ray lying in the disc's plane
// gives its chord of the disc.
Interval intersect(const Ray& ray, const Disc& disc);

// The ball. Tangent ray: [t, t].
Interval intersect(const Ray& ray, const Sphere& sphere);

// The solid frustum (convex, so one interval). Ray parallel to the axis: the height slab
// if the ray is within the radius (a frustum of varying radius is then entered at its side).
Interval intersect(const Ray& ray, const Frustum& frustum);

// The solid torus: up to two intervals (four crossings of the quartic). Computed from the real
// roots of the ray–torus quartic (origin first moved to the ray's closest point to the centre
// to avoid cancellation), with membership decided at chord midpoints.
IntervalPair intersect(const Ray& ray, const Torus& torus);

}  // namespace cwe
