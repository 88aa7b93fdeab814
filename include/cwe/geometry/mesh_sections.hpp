#pragma once
// Plane sections of a closed triangle mesh, for many point-inside queries on few planes: the
// polyhedral engagement's section of a removal volume by the plane of each axial disc of the
// cutter (Aras 2008 §6.2; docs/engagement.md), read in 2-D.
//
// The planes are normal to one axis (the local z of a frame). A section is the set of segments
// where the triangles cross the plane; a point of the plane is inside when a ray from it along
// +u crosses them an odd number of times. The section is that of the plane moved down by an
// infinitesimal (a vertex on the plane counts as above it), so that a face lying in the plane (a
// floor at a disc's height) and vertices on it give a consistent set of closed loops: every
// crossing edge yields one point, computed the same way from both its triangles. The mesh may be
// several closed meshes that touch along faces (the pieces of one move's removal volume): their
// common faces cancel in the count.

#include <array>
#include <cstdint>
#include <vector>

#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/geometry/vec.hpp"

namespace cwe {

class MeshSection {
 public:
  bool empty() const { return segments_.empty(); }
  // Is (u, v) inside (strictly, up to points on the section's boundary)?
  bool contains(double u, double v) const;

 private:
  friend class MeshSlicer;
  struct Segment {
    double u0, v0, u1, v1;
  };
  void index();
  std::vector<Segment> segments_;
  // The segments by stripes of v: those of stripe k are bin_[start_[k] .. start_[k + 1]).
  double v_min_ = 0.0, v_max_ = 0.0, per_stripe_ = 0.0;
  std::vector<std::uint32_t> start_, bin_;
};

class MeshSlicer {
 public:
  // The mesh with its vertices in the coordinates (u, v, w) of `frame` (frame.to_local).
  MeshSlicer(const TriangleMesh& mesh, const Frame& frame);
  const Frame& frame() const { return frame_; }
  // The section by the plane w = h (local coordinates), lowered by an infinitesimal.
  MeshSection section(double h) const;

 private:
  Frame frame_;
  std::vector<Vec3> local_;  // the vertices in the frame
  std::vector<std::array<int, 3>> triangles_;
  // The triangles whose w span meets layer k of [w_min_, w_max_]: layer_[start_[k] ..
  // start_[k + 1]).
  double w_min_ = 0.0, w_max_ = 0.0, per_layer_ = 0.0;
  std::vector<std::uint32_t> start_, layer_;
};

}  // namespace cwe
