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
//    sweep, and conversely (Aras 2008 §4.2.4).
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
  // `parts` must outlive the sweep.
  MoveSweep(const ConvexParts& parts, const Move& move);

  const std::vector<LinearSweep>& pieces() const { return pieces_; }
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
  int path_pieces_ = 1;
  double deviation_bound_ = 0.0;
};

}  // namespace cwe
