#include "cwe/envelope/swept_volume.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {
namespace {

// Segments of a circle of radius r whose chords deviate at most `deviation`: the sagitta
// r(1 - cos(θ/2)) of each step θ stays below it.
int steps_for(double radius, double angle, double deviation) {
  if (radius <= deviation || angle <= 0.0) return 1;
  const double step = 2.0 * std::acos(1.0 - deviation / radius);
  return std::max(1, static_cast<int>(std::ceil(angle / step - tol::kRelative)));
}

Frame frame_at(const Vec3& tip, const Vec3& axis) {
  return Frame::from_z(tip, axis, Vec3::UnitX());
}

}  // namespace

bool is_convex(const Cutter& cutter) {
  // Concave ρ(z): lines and counter-clockwise (convex) arcs only, with the slope dρ/dz not
  // increasing at the joints (tangent turning clockwise in (ρ, z), i.e. to the left when going
  // up: cross product of consecutive tangents ≥ 0).
  const auto& segments = cutter.profile().segments();
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (segments[i].kind == ProfileSegment::Kind::kArc && !segments[i].counterclockwise)
      return false;
    if (i == 0) continue;
    const Vec2 a = segments[i - 1].tangent_at(1.0);
    const Vec2 b = segments[i].tangent_at(0.0);
    if (a.x() * b.y() - a.y() * b.x() < -tol::kAngle) return false;
  }
  // The top edge turns inwards (towards the axis) from the last piece: convex as long as the last
  // piece does not point back down, which a rising profile never does.
  return true;
}

std::vector<Vec3> tool_surface_points(const Cutter& cutter, double tolerance) {
  const double half = tolerance / 2.0;
  std::vector<Vec2> profile;  // (ρ, z) samples, tip to top edge
  for (const ProfileSegment& s : cutter.profile().segments()) {
    const int steps = s.kind == ProfileSegment::Kind::kArc
                          ? steps_for(s.radius, std::abs(s.end_angle() - s.start_angle()), half)
                          : 1;
    for (int k = profile.empty() ? 0 : 1; k <= steps; ++k) {
      profile.push_back(s.point_at(static_cast<double>(k) / steps));
    }
  }
  std::vector<Vec3> points;
  points.emplace_back(0.0, 0.0, cutter.profile().height());  // centre of the top disc
  for (const Vec2& p : profile) {
    if (p.x() <= 0.0) {
      points.emplace_back(0.0, 0.0, p.y());
      continue;
    }
    const int ring = std::max(8, steps_for(p.x(), kTwoPi, half));
    for (int j = 0; j < ring; ++j) {
      const double phi = kTwoPi * j / ring;
      points.emplace_back(p.x() * std::sin(phi), p.x() * std::cos(phi), p.y());
    }
  }
  return points;
}

SweptVolume swept_volume(const Cutter& cutter, const Move& move,
                         const SweptVolumeOptions& options) {
  if (!(options.tolerance > 0.0)) {
    throw InputError(
        fmt::format("swept-volume tolerance {} mm: expected a positive length", options.tolerance));
  }
  if (!is_convex(cutter)) {
    throw InputError(SourceLocation{cutter.name()},
                     "swept volumes are built for convex cutters (every APT cutter); this "
                     "profile has a concave part");
  }
  const double half = options.tolerance / 2.0;
  // Subdivision: the path's chords deviate at most tolerance/2 from an arc, and the axis turns
  // at most Δ per piece so that no tool point (within `reach` of the tip) moves more than
  // tolerance/2 from the piece's mean-axis tool: reach·Δ/2 ≤ tolerance/2.
  const BoundingCylinder bounds = cutter.bounding_cylinder();
  const double reach = std::hypot(bounds.radius, bounds.z_max);
  int pieces = 1;
  if (move.is_arc()) {
    pieces = std::max(pieces, steps_for(move.radius(), move.sweep, half));
  }
  const double turn = move.axis_angle();
  if (turn > tol::kAngle) {
    pieces = std::max(pieces, static_cast<int>(std::ceil(turn * reach / options.tolerance)));
  }
  const std::vector<Vec3> tool = tool_surface_points(cutter, options.tolerance);
  SweptVolume result;
  const bool curved = pieces > 1 || move.is_arc() || turn > tol::kAngle;
  result.deviation_bound = curved ? 2.0 * options.tolerance : options.tolerance;
  for (int k = 0; k < pieces; ++k) {
    const double u0 = static_cast<double>(k) / pieces;
    const double u1 = static_cast<double>(k + 1) / pieces;
    result.pieces.push_back(
        linear_piece_mesh(tool, move.position(u0), move.position(u1), move.axis(0.5 * (u0 + u1))));
  }
  return result;
}

TriangleMesh linear_piece_mesh(const std::vector<Vec3>& tool, const Vec3& start, const Vec3& end,
                               const Vec3& axis) {
  std::vector<Vec3> points;
  points.reserve(2 * tool.size());
  for (const Vec3& tip : {start, end}) {
    const Frame frame = frame_at(tip, axis);
    for (const Vec3& p : tool) points.push_back(frame.to_world(p));
  }
  return convex_hull(points);
}

}  // namespace cwe
