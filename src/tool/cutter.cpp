#include "cwe/tool/cutter.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cwe/core/assert.hpp"
#include "cwe/core/error.hpp"
#include "cwe/geometry/intersect.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/tool/piece_chord.hpp"

namespace cwe {
namespace {

PatchKind classify(const ProfileSegment& s) {
  if (s.kind == ProfileSegment::Kind::kArc) {
    return std::abs(s.center.x()) <= tol::kLength ? PatchKind::kSphere : PatchKind::kTorus;
  }
  if (s.is_horizontal()) return s.start.y() == 0.0 ? PatchKind::kFlatBottom : PatchKind::kStep;
  if (s.is_vertical()) return PatchKind::kCylinder;
  return PatchKind::kCone;
}

Vec3 revolve(const Vec2& rho_z, double phi) {
  return {rho_z.x() * std::sin(phi), rho_z.x() * std::cos(phi), rho_z.y()};
}

// Closure of a \ b for one interval a and sorted disjoint intervals b.
std::vector<Interval> subtract(const Interval& a, const std::vector<Interval>& b) {
  std::vector<Interval> out;
  if (a.is_empty()) return out;
  double lo = a.lo;
  for (const Interval& cut : b) {
    if (cut.is_empty() || cut.hi < lo || cut.lo > a.hi) continue;
    if (cut.lo > lo) out.push_back({lo, cut.lo});
    lo = std::max(lo, cut.hi);
  }
  if (lo <= a.hi && (out.empty() || lo > out.back().hi)) out.push_back({lo, a.hi});
  // A cut that covers an end entirely leaves a degenerate closure point only where a touches
  // the tube from outside, which is what the closed set demands.
  return out;
}

void validate_options(const CutterOptions& o) {
  const SourceLocation where{o.name.empty() ? "tool" : o.name};
  if (o.flutes < 0 || o.flutes > 100) {
    throw InputError(where, fmt::format("flutes = {}: expected a count from 1 to 100", o.flutes));
  }
  if (!(o.helix_angle_deg > -90.0 && o.helix_angle_deg < 90.0)) {
    throw InputError(where, fmt::format("helix angle = {}°: expected a value in (-90°, 90°)",
                                        o.helix_angle_deg));
  }
  if (o.shank && (!(o.shank->diameter > 0.0) || !(o.shank->length >= 0.0))) {
    throw InputError(where, fmt::format("shank diameter {} and length {}: the diameter must be "
                                        "positive and the length not negative",
                                        o.shank->diameter, o.shank->length));
  }
}

}  // namespace

const char* to_string(PatchKind kind) {
  switch (kind) {
    case PatchKind::kFlatBottom:
      return "flat bottom";
    case PatchKind::kStep:
      return "step";
    case PatchKind::kCylinder:
      return "cylinder";
    case PatchKind::kCone:
      return "cone";
    case PatchKind::kSphere:
      return "sphere";
    case PatchKind::kTorus:
      return "torus";
  }
  return "?";
}

Cutter::Cutter(Profile profile, CutterOptions options)
    : profile_(std::move(profile)), name_(std::move(options.name)), apt_(options.apt) {
  validate_options(options);
  const auto& segments = profile_.segments();
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const ProfileSegment& s = segments[i];
    patches_.push_back({classify(s), static_cast<int>(i), {s.max_radius(), s.min_z(), s.max_z()}});
  }
  // Ball and pointed tips cut with few flutes; flat-bottomed tools commonly carry four.
  flutes_ = options.flutes > 0 ? options.flutes
                               : (patches_.front().kind == PatchKind::kFlatBottom ? 4 : 2);
  helix_angle_ = degrees_to_radians(options.helix_angle_deg);
  shank_ = options.shank.value_or(Shank{2.0 * profile_.top_radius(), 4.0 * profile_.top_radius()});
}

const ProfileSegment& Cutter::segment_of(int patch) const {
  CWE_ASSERT(patch >= 0 && patch < static_cast<int>(patches_.size()), "patch index out of range");
  return profile_
      .segments()[static_cast<std::size_t>(patches_[static_cast<std::size_t>(patch)].segment)];
}

BoundingCylinder Cutter::bounding_cylinder() const {
  return {profile_.max_radius(), 0.0, profile_.height()};
}

Vec3 Cutter::point(int patch, double phi, double u) const {
  return revolve(segment_of(patch).point_at(u), phi);
}

Vec3 Cutter::normal(int patch, double phi, double u) const {
  return revolve(segment_of(patch).normal_at(u), phi);
}

double Cutter::implicit_value(int patch, const Vec3& p) const {
  const ProfileSegment& s = segment_of(patch);
  switch (patches_[static_cast<std::size_t>(patch)].kind) {
    case PatchKind::kFlatBottom:
    case PatchKind::kStep: {
      const Vec2 n = s.normal_at(0.0);  // (0, ±1): faces down under the solid, up over a step
      return cwe::implicit_value(Plane{Vec3(0.0, 0.0, s.start.y()), Vec3(0.0, 0.0, n.y())}, p);
    }
    case PatchKind::kCylinder:
    case PatchKind::kCone:
      return cwe::implicit_value(frustum_of(s), p);
    case PatchKind::kSphere:
      return cwe::implicit_value(Sphere{Vec3(0.0, 0.0, s.center.y()), s.radius}, p);
    case PatchKind::kTorus: {
      // A concave (clockwise) corner has the solid outside its tube.
      const double v = cwe::implicit_value(torus_of(s), p);
      return s.counterclockwise ? v : -v;
    }
  }
  return 0.0;
}

std::vector<Interval> Cutter::intersect_patch(int patch, const Ray& ray) const {
  const ProfileSegment& s = segment_of(patch);
  std::vector<Interval> out;
  if (s.kind == ProfileSegment::Kind::kLine || s.counterclockwise) {
    const Interval chord = convex_piece_chord(s, ray);
    if (!chord.is_empty()) out.push_back(chord);
    return out;
  }
  // Concave corner: ρ ≤ c_ρ - √(r² - (z - c_z)²) is the core cylinder minus the tube.
  const Interval band = height_slab(ray, s.min_z(), s.max_z());
  if (band.is_empty()) return out;
  std::vector<Interval> tube;
  for (const Interval& i : cwe::intersect(ray, torus_of(s))) {
    const Interval clipped = cwe::intersect(i, band);
    if (!clipped.is_empty()) tube.push_back(clipped);
  }
  for (const Interval& i : subtract(core_chord(s, ray), tube)) {
    if (!i.is_empty()) out.push_back(i);
  }
  const double scale = ray.direction.norm();
  return normalize(std::move(out), scale > 0.0 ? tol::kLength / scale : 0.0);
}

std::vector<Interval> Cutter::intersect(const Ray& ray) const {
  std::vector<Interval> all;
  for (std::size_t i = 0; i < patches_.size(); ++i) {
    const auto part = intersect_patch(static_cast<int>(i), ray);
    all.insert(all.end(), part.begin(), part.end());
  }
  const double scale = ray.direction.norm();
  return normalize(std::move(all), scale > 0.0 ? tol::kLength / scale : 0.0);
}

bool Cutter::contains(const Vec3& p) const {
  return profile_.contains(std::hypot(p.x(), p.y()), p.z());
}

EngagementCoordinates Cutter::engagement_coordinates(const Vec3& p) const {
  const double rho = std::hypot(p.x(), p.y());
  double phi = std::atan2(p.x(), p.y());  // x = ρ sin φ, y = ρ cos φ
  if (phi < 0.0) phi += kTwoPi;
  const Profile::Location loc = profile_.closest(Vec2(rho, p.z()));
  const ProfileSegment& s = profile_.segments()[static_cast<std::size_t>(loc.segment)];
  const Vec2 q = s.point_at(loc.u);
  EngagementCoordinates c;
  c.patch = loc.segment;  // one patch per profile piece, same order
  c.phi = phi;
  c.depth = q.y();
  c.radius = q.x();
  c.u = loc.u;
  c.distance = loc.distance;
  c.polar = patches_[static_cast<std::size_t>(loc.segment)].kind == PatchKind::kFlatBottom;
  return c;
}

}  // namespace cwe
