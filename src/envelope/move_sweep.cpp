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

MoveSweep::MoveSweep(const ConvexParts& parts, const Move& move) : move_(move), parts_(&parts) {
  const double tolerance = parts.tolerance();
  const BoundingCylinder b = parts.cutter().bounding_cylinder();
  const double reach = std::hypot(b.radius, b.z_max);
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
  for (int k = 0; k < path_pieces_; ++k) {
    const double u0 = static_cast<double>(k) / path_pieces_;
    const double u1 = static_cast<double>(k + 1) / path_pieces_;
    const Vec3 axis = exact ? move.start_axis.normalized() : move.axis(0.5 * (u0 + u1));
    const Vec3 a = k == 0 ? move.start : move.position(u0);
    const Vec3 e = k + 1 == path_pieces_ ? move.end : move.position(u1);
    for (const ConvexParts::Part& part : parts.parts()) {
      pieces_.emplace_back(*part.cutter, a + part.offset * axis, e + part.offset * axis, axis);
    }
  }
}

Aabb MoveSweep::bounds() const {
  Aabb box;
  for (const LinearSweep& piece : pieces_) box.extend(piece.bounds());
  return box;
}

}  // namespace cwe
