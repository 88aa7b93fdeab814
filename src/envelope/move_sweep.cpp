#include "cwe/envelope/move_sweep.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/envelope/swept_volume.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {
namespace {

// A sweep is cut into at most this many pieces along its path (their memory is held together).
constexpr double kMostPathPieces = 1e6;

// Steps of a circle of radius r whose chords have sagitta r(1 - cos(θ/2)) ≤ deviation, as a
// double (checked against kMostPathPieces before any cast).
double steps_for(double radius, double angle, double deviation) {
  if (radius <= deviation || angle <= 0.0) return 1.0;
  const double step = 2.0 * std::acos(1.0 - deviation / radius);
  return std::max(1.0, std::ceil(angle / step - tol::kRelative));
}

// `pieces` as an int, or an InputError that blames the tolerance (or the move).
int checked_pieces(double pieces, double tolerance, const Move& move) {
  if (pieces <= kMostPathPieces) return static_cast<int>(pieces);
  throw InputError(SourceLocation{"--tolerance"},
                   fmt::format("{:g} mm would cut the move at line {} into {:.3g} pieces, more "
                               "than {:g}: raise the tolerance (or check the move)",
                               tolerance, move.line, pieces, kMostPathPieces));
}

// A convex slab: a flat bottom out to the piece's lower radius (none on the axis), then the
// piece, lowered to start at height 0.
Cutter slab(const Cutter& cutter, const ProfileSegment& piece, int index) {
  const double z0 = piece.start.y();
  const Vec2 down(0.0, z0);
  std::vector<ProfileSegment> segments;
  if (piece.start.x() > 0.0)
    segments.push_back(ProfileSegment::line({0.0, 0.0}, piece.start - down));
  if (piece.kind == ProfileSegment::Kind::kLine) {
    segments.push_back(ProfileSegment::line(piece.start - down, piece.end - down));
  } else {
    segments.push_back(ProfileSegment::arc(piece.start - down, piece.end - down,
                                           piece.center - down, piece.counterclockwise));
  }
  CutterOptions options;
  options.name = fmt::format("{} (part {})", cutter.name(), index + 1);
  options.shank = Shank{1.0, 1.0};  // unused: parts only cut
  return Cutter(Profile(std::move(segments), options.name), options);
}

// How high above its tip, and how far from it, a point of a tool of largest radius `radius` can
// lie while inside `region`, anywhere along `move` (upper bounds). Every tip position lies in
// the path's box, so no point of the region is farther from the tip than the farthest pair of
// the two boxes' points. And where every axis of the move has a positive component n·a along
// the outward normal n of one of the region's faces, a tool point at height h above the tip
// lies at least n·p + h·(n·a) − radius along n, beyond the face once h passes
// (face − min n·p + radius)/(n·a): the tool's part that can be inside is no higher. The axes
// slerp along a great-circle arc shorter than π, on which n·a is smallest at an end; a piece's
// axis lies on that arc and its tip on the path or a chord of it, so the bounds hold for the
// pieces too.
struct Within {
  double height = 0.0;
  double reach = 0.0;
};
Within within(const Aabb& region, const Move& move, double radius) {
  const Aabb path = move.bounds();
  double farthest = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double d = std::max(region.max[i] - path.min[i], path.max[i] - region.min[i]);
    farthest += d * d;
  }
  Within w;
  w.height = w.reach = std::sqrt(farthest);
  const Vec3 a0 = move.axis(0.0), a1 = move.axis(1.0);
  for (int i = 0; i < 3; ++i) {
    for (const double side : {1.0, -1.0}) {
      const double along = std::min(side * a0[i], side * a1[i]);
      if (!(along > 0.0)) continue;
      const double face = side > 0.0 ? region.max[i] : -region.min[i];
      const double nearest = side > 0.0 ? path.min[i] : -path.max[i];
      const double height = std::max(0.0, (face - nearest + radius) / along);
      w.height = std::min(w.height, height);
      w.reach = std::min(w.reach, std::hypot(radius, height));
    }
  }
  return w;
}

// The box of a tool's part up to `height` above its tip at `tip` along unit `axis` (a cylinder
// of `radius` about that stretch of the axis).
Aabb part_box(const Vec3& tip, const Vec3& axis, double height, double radius) {
  Aabb box;
  box.extend(tip);
  box.extend(tip + height * axis);
  for (int i = 0; i < 3; ++i) {
    const double e = radius * std::sqrt(std::max(0.0, 1.0 - axis[i] * axis[i]));
    box.min[i] -= e;
    box.max[i] += e;
  }
  return box;
}

}  // namespace

ConvexParts::ConvexParts(const Cutter& cutter, double tolerance)
    : cutter_(&cutter), tolerance_(tolerance) {
  if (!std::isfinite(tolerance) || tolerance <= 0.0) {
    throw InputError(fmt::format("sweep tolerance {} mm: expected a positive length", tolerance));
  }
  if (is_convex(cutter)) {
    parts_.push_back({&cutter, 0.0});
    return;
  }
  // Lines and convex arcs become slabs as they are; concave arcs become chord polylines.
  std::vector<ProfileSegment> pieces;
  for (const ProfileSegment& s : cutter.profile().segments()) {
    if (s.is_horizontal()) continue;  // no volume: the neighbouring slabs' faces cover it
    if (s.kind == ProfileSegment::Kind::kLine || s.counterclockwise) {
      pieces.push_back(s);
      continue;
    }
    const double count = steps_for(s.radius, std::abs(s.end_angle() - s.start_angle()), tolerance);
    if (!(count <= kMostPathPieces)) {
      throw InputError(SourceLocation{"--tolerance"},
                       fmt::format("{:g} mm would cut a concave arc of the cutter's profile into "
                                   "{:.3g} pieces, more than {:g}: raise the tolerance",
                                   tolerance, count, kMostPathPieces));
    }
    const int steps = static_cast<int>(count);
    const double sagitta =
        s.radius * (1.0 - std::cos(std::abs(s.end_angle() - s.start_angle()) / (2.0 * steps)));
    deviation_ = std::max(deviation_, sagitta);
    for (int k = 0; k < steps; ++k) {
      pieces.push_back(ProfileSegment::line(s.point_at(static_cast<double>(k) / steps),
                                            s.point_at(static_cast<double>(k + 1) / steps)));
    }
  }
  owned_.reserve(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    owned_.push_back(slab(cutter, pieces[i], static_cast<int>(i)));
  }
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    parts_.push_back({&owned_[i], pieces[i].start.y()});
  }
}

MoveSweep::MoveSweep(const ConvexParts& parts, const Move& move, const Aabb& region,
                     PieceReach piece_reach)
    : move_(move), parts_(&parts) {
  const double tolerance = parts.tolerance();
  const BoundingCylinder b = parts.cutter().bounding_cylinder();
  double reach = std::hypot(b.radius, b.z_max);
  // Only the tool's part that can enter the region cuts: above `height` nothing does.
  double height = b.z_max;
  if (!region.is_empty()) {
    const Within w = within(region, move, b.radius);
    height = std::min(height, w.height);
    // Tool points that never enter the region cut nothing, however far the pieces move them.
    if (piece_reach == PieceReach::kRegion) reach = std::min(reach, w.reach);
  }
  if (move.is_arc()) {
    path_pieces_ =
        std::max(path_pieces_,
                 checked_pieces(steps_for(move.radius(), move.sweep, tolerance), tolerance, move));
  }
  const double turn = move.axis_angle();
  if (turn > tol::kAngle) {
    // The mean axis is within turn/(2·pieces) of every axis of its piece.
    path_pieces_ = std::max(
        path_pieces_, checked_pieces(std::ceil(turn * reach / (2.0 * tolerance)), tolerance, move));
  }
  const bool turning = turn > tol::kAngle;
  const bool exact = !move.is_arc() && !turning;
  // The path's sagitta and the axis turn each move a tool point by at most the tolerance; the
  // parts exceed the tool by at most their deviation.
  deviation_bound_ =
      (move.is_arc() ? tolerance : 0.0) + (turning ? tolerance : 0.0) + parts.deviation();
  pieces_.reserve(static_cast<std::size_t>(path_pieces_) * parts.parts().size());
  reach_bounds_.reserve(pieces_.capacity());
  for (int k = 0; k < path_pieces_; ++k) {
    const double u0 = static_cast<double>(k) / path_pieces_;
    const double u1 = static_cast<double>(k + 1) / path_pieces_;
    const Vec3 axis = exact ? move.start_axis.normalized() : move.axis(0.5 * (u0 + u1));
    const Vec3 a = k == 0 ? move.start : move.position(u0);
    const Vec3 e = k + 1 == path_pieces_ ? move.end : move.position(u1);
    Aabb reach_box;  // the part up to `height` at both ends of the path piece
    if (height < b.z_max) {
      reach_box = part_box(a, axis, height, b.radius);
      reach_box.extend(part_box(e, axis, height, b.radius));
    }
    for (const ConvexParts::Part& part : parts.parts()) {
      pieces_.emplace_back(*part.cutter, a + part.offset * axis, e + part.offset * axis, axis);
      Aabb box = pieces_.back().bounds();
      if (!reach_box.is_empty()) {
        box.min = box.min.cwiseMax(reach_box.min);
        box.max = box.max.cwiseMin(reach_box.max);
      }
      reach_bounds_.push_back(box);
    }
  }
}

Aabb MoveSweep::bounds() const {
  Aabb box;
  for (const LinearSweep& piece : pieces_) box.extend(piece.bounds());
  return box;
}

}  // namespace cwe
