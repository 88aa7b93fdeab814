#pragma once
// A curved move's linear pieces, for the workpieces that read a move's removal volume
// RV = W ∩ SV at its locations (the mesh and the B-rep ones): a move that comes back over its own
// path (a helix's turns, a full circle's end) has material in its RV in front of the tool at a
// location that it took before reaching there. A point is taken when it lies deeper than a
// margin inside one of the move's pieces before the location's.

#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

#include "cwe/envelope/move_sweep.hpp"

namespace cwe {

class MovePieces {
 public:
  // Axes closer than this (cosine) count as one: 1e-6 rad, under 1e-5 mm across a 10 mm cutter.
  static constexpr double kSameAxis = 1.0 - 5e-13;

  MovePieces() = default;
  // Keeps the pieces of a move in several pieces with one axis (an arc, a helix). Not those of a
  // simultaneous 5-axis move, whose pieces' tips may all lie close together while the axis
  // turns: which piece a step starts in is not told by its tip.
  explicit MovePieces(const MoveSweep& sweep) {
    if (sweep.pieces().empty()) return;
    const Vec3 axis = sweep.pieces().front().axis().normalized();
    for (const LinearSweep& piece : sweep.pieces()) {
      if (!(piece.axis().normalized().dot(axis) > kSameAxis)) return;
    }
    axis_ = axis;
    if (sweep.pieces().size() > 1) pieces_ = sweep.pieces();
  }

  // The axis all the move's pieces share, if they do.
  const std::optional<Vec3>& axis() const { return axis_; }

  // The number of pieces wholly before a step that starts at tip `start`: those before the piece
  // nearest it (the first of equals: a circle's start is also its end, and a step there starts
  // the circle; a step that starts on a joint starts the later piece, whose start is as near,
  // but the piece before it holds no point the step cuts). 0 for a move in one piece.
  std::size_t before(const Vec3& start) const {
    std::size_t nearest = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < pieces_.size(); ++k) {
      const Vec3 a = pieces_[k].start(), d = pieces_[k].end() - a;
      const double along = d.squaredNorm() > 0.0 ? (start - a).dot(d) / d.squaredNorm() : 0.0;
      const double gap = (a + std::clamp(along, 0.0, 1.0) * d - start).norm();
      if (gap < best) {
        best = gap;
        nearest = k;
      }
    }
    return nearest;
  }

  // The same for the step `step` (a part of the move): 0 when either has no pieces.
  std::size_t before(const MoveSweep& step) const {
    return step.pieces().empty() ? 0 : before(step.pieces().front().start());
  }

  // Is `point` deeper than `margin` along the unit `normal` (both ways) inside one of the first
  // `count` pieces?
  bool swept_before(const Vec3& point, const Vec3& normal, std::size_t count, double margin) const {
    for (std::size_t k = 0; k < std::min(count, pieces_.size()); ++k) {
      if (!pieces_[k].bounds().contains(point)) continue;
      const Interval in = pieces_[k].chord(Ray{point, normal});
      if (in.lo < -margin && in.hi > margin) return true;
    }
    return false;
  }

 private:
  std::optional<Vec3> axis_;
  std::vector<LinearSweep> pieces_;
};

}  // namespace cwe
