#pragma once
// The volume a cutter sweeps along one move, as a union of exact linear sweeps of convex tool
// parts: what the workpiece backends remove (Aras 2008 ch. 4).
//
//  - The tool: an APT cutter is convex and is its own single part. A general profile with
//    concave parts (corner-rounding tools, undercut shapes from JSON profiles) is cut at its
//    joints into slabs { z within one piece's height range, ρ ≤ that piece's radius }: a line or
//    a convex arc gives a convex slab, and the union of the slabs is the tool. A concave arc is
//    replaced by the polyline of its chords with sagitta ≤ the tolerance, which lies outside the
//    arc, so the parts hold the tool and exceed it by at most the tolerance.
//  - The move: a line with a constant axis (3-axis, 3+2) is one exact piece. Arcs, helices and
//    simultaneous 5-axis lines are cut into linear pieces between points of the true path, each
//    swept with the axis at its middle, until the path's sagitta stays within the tolerance and
//    the axis turns by less than 2·tolerance/reach per piece (reach: the farthest tool point from
//    the tip), so every tool point of the true motion lies within the tolerance of a piece's
//    sweep, and conversely (Aras 2008 §4.2.4). Given the region that holds the material, reach
//    is only that of the tool's points that can enter it (a piece's tool is rigid, its tip on
//    the path or a chord of it, its axis on the arc of the true axes): no farther from the tip
//    than any point of the region from any point of the path, and no higher along the axis
//    than where the tool clears a face of the region that every axis of the move points out
//    of. Points beyond cut nothing, however far the pieces move them: a 50 mm tool tilting a
//    few millimetres into the stock needs a fraction of the pieces.
// `deviation_bound()` is the resulting Hausdorff bound: 0 for exact sweeps (to rounding), the
// tolerance for each of: an arc path, a turning axis, a concave profile part.

#include <vector>

#include "cwe/envelope/linear_sweep.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/move.hpp"

namespace cwe {

// A cutter as convex parts stacked along its axis. Built once per tool.
class ConvexParts {
 public:
  // The cutter must outlive this object (a convex cutter is used in place). Throws InputError
  // for a tolerance that is not positive.
  ConvexParts(const Cutter& cutter, double tolerance);
  ConvexParts(Cutter&&, double) = delete;

  struct Part {
    const Cutter* cutter = nullptr;  // convex, tip at `offset` above the real tip
    double offset = 0.0;             // mm along the axis
  };
  const std::vector<Part>& parts() const { return parts_; }
  const Cutter& cutter() const { return *cutter_; }
  // 0 when the parts are the tool exactly, else the largest concave-arc sagitta.
  double deviation() const { return deviation_; }
  double tolerance() const { return tolerance_; }

  ConvexParts(const ConvexParts&) = delete;
  ConvexParts& operator=(const ConvexParts&) = delete;

 private:
  const Cutter* cutter_;
  std::vector<Cutter> owned_;
  std::vector<Part> parts_;
  double deviation_ = 0.0;
  double tolerance_ = 0.0;
};

// The linear pieces of one move, each for each convex part.
class MoveSweep {
 public:
  // How many pieces a turning axis needs: enough for the whole tool's reach, or for the reach
  // of its part that can enter the region only.
  enum class PieceReach { kWholeTool, kRegion };
  // `parts` must outlive the sweep. `region`: a box holding all the material the sweep will
  // meet (an empty box: unknown). With PieceReach::kRegion the deviation bound holds within the
  // region only.
  MoveSweep(const ConvexParts& parts, const Move& move, const Aabb& region = Aabb(),
            PieceReach piece_reach = PieceReach::kRegion);

  const std::vector<LinearSweep>& pieces() const { return pieces_; }
  // Piece i's box, cut down to the part of the tool that can enter the region (its bounds()
  // without a region): every stretch of its sweep within the region lies in it, so a backend
  // that removes by the box reaches fewer rays for the same removal.
  const Aabb& reach_bounds(std::size_t i) const { return reach_bounds_[i]; }
  // Number of path pieces the move was cut into (1 for an exact linear move).
  int path_pieces() const { return path_pieces_; }
  double deviation_bound() const { return deviation_bound_; }
  Aabb bounds() const;
  // The move and the tool's parts it was built from (a backend may sweep them its own way).
  const Move& move() const { return move_; }
  const ConvexParts& parts() const { return *parts_; }

 private:
  Move move_;
  const ConvexParts* parts_;
  std::vector<LinearSweep> pieces_;
  std::vector<Aabb> reach_bounds_;  // one per piece
  int path_pieces_ = 1;
  double deviation_bound_ = 0.0;
};

}  // namespace cwe
