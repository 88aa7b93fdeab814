#pragma once
// Closed triangle meshes of the volume a cutter sweeps along a move.
//
// Every APT cutter is a convex solid (its radius is a concave function of height: bottom line,
// convex corner arc, side line). A convex tool translated along a segment sweeps the convex hull
// of its two end positions (Minkowski sum with the segment): the back half at the start, the
// envelope (the grazing curve swept along the move, Aras 2008 ch. 3) and the front half at the
// end. So a linear 3-axis or 3+2 move gives one closed mesh: the hull of the tessellated tool at
// both ends.
//
// Arcs, helices and simultaneous 5-axis moves are cut into linear pieces, each swept by the tool
// at the piece's mean axis (Aras 2008 §4.2.4), until the path's sagitta and the axis turn keep
// every point of the true tool within the tolerance of a piece; the result is one closed mesh per
// piece, whose union is the swept volume.
//
// Accuracy: the tool is tessellated with rings and profile samples whose chords deviate less than
// tolerance/2 each, so each piece is an inscribed polytope of its exact sweep, deeper than it by
// less than the tolerance; the union of the pieces lies within `deviation_bound` of the true swept
// volume (Hausdorff distance). Non-convex profiles (general JSON profiles such as
// corner-rounding tools) are refused: their sweep is not a hull.

#include <vector>

#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/move.hpp"

namespace cwe {

struct SweptVolumeOptions {
  double tolerance = 0.01;  // mm: bound on the chord deviation of tessellation and subdivision
};

struct SweptVolume {
  std::vector<TriangleMesh> pieces;  // closed meshes whose union is the swept volume
  double deviation_bound = 0.0;      // mm, see above
};

// Points of the tool surface in the TCS whose convex hull is within `tolerance` of the tool.
std::vector<Vec3> tool_surface_points(const Cutter& cutter, double tolerance);

// The closed mesh of one linear piece: the convex hull of `tool` (tool_surface_points, TCS) placed
// at tip `start` and at tip `end` with unit `axis` (the tool frame's x as close to world X as the
// axis allows, so that pieces of one tool share their faceting).
TriangleMesh linear_piece_mesh(const std::vector<Vec3>& tool, const Vec3& start, const Vec3& end,
                               const Vec3& axis);
// The same with the axis turning by θ from unit `start_axis` to unit `end_axis` (a piece of a
// simultaneous 5-axis move): the hull of the tool at each end in its own pose. It holds both true
// end tools, where a mean axis's tool reaches up to reach·θ/2 beyond the true one at each end
// (material the next move's first location is still to cut). Where the union of the two poses
// is concave the hull fills it, by no more than the mean axis's reach·θ/2: a point λ·a + (1−λ)·b
// of the hull (a, b on the tools at start and end) lies within 2λ(1−λ)·reach·θ of the tool at
// the motion's fraction 1−λ, and so by about z·θ beside an end tool at height z.
TriangleMesh linear_piece_mesh(const std::vector<Vec3>& tool, const Vec3& start,
                               const Vec3& start_axis, const Vec3& end, const Vec3& end_axis);

// The volume a convex cutter sweeps along a planar arc (no advance along its normal) with its
// axis along the arc's normal, as a few closed meshes whose union it is: the tool's meridian
// section revolved about the arc's axis (stations with chords within path_tolerance/2 at the
// outer radius), and the faceted tool at both ends (rings of an even number of sides and profile
// samples, chords within tolerance/2, with vertices on the end sections).
//  - One mesh where the inner wall stays off the arc's axis (R − ρmax > max(tolerance/2, 1 µm))
//    and the half tools off each other (sweep + 2·asin(ρmax/R) < 2π): the tube closed by the
//    tool's back half at the start and front half at the end; a full circle (or more) is the
//    revolved ring alone, whatever R.
//  - Else three, for a union: the wedge (the section's inner side clamped at the arc's axis,
//    which the union of the tool's positions covers from every angle of the arc: the cake slice
//    around a corner that an arc of R ≤ ρmax turns), and the whole tool at each end (which holds
//    the points of the swept volume outside the wedge's angles).
// Empty for any other move or axis (the move is then cut in linear pieces).
std::vector<TriangleMesh> planar_arc_sweep(const Cutter& cutter, double tolerance,
                                           double path_tolerance, const Move& arc);

// Is the cutter's solid convex (radius a concave function of height)?
bool is_convex(const Cutter& cutter);

// Volumes from the profile alone (1-D quadrature, a relative error near 1e-8; no meshes), for a
// convex cutter: what exact sweeps must measure (the B-rep workpiece checks its solids by them).
// The cutter's volume, π∫ρ² dz.
double cutter_volume(const Cutter& cutter);
// The volume swept along the segment d (tool frame, any length) with a constant axis: the
// Minkowski sum's V(T) + |d|·A(d̂), the shadow's area A by Cauchy's formula ½∮|n·d̂| dS.
double line_swept_volume(const Cutter& cutter, const Vec3& d);
// The volume swept along a planar arc of radius `radius` (the tip's distance from the arc's
// axis) through `sweep` radians (≥ 2π: a full ring), the axis along the arc's normal: slice by
// slice, the area a disc sweeps (the annular strip and the end half discs off the arc's axis;
// over it, the sector and what the end discs reach beyond it). Off the axis the end half discs
// must not overlap: sweep + 2·asin(ρmax/R) ≤ 2π.
double planar_arc_swept_volume(const Cutter& cutter, double radius, double sweep);

// Throws InputError for a non-convex cutter or a tolerance that is not positive.
SweptVolume swept_volume(const Cutter& cutter, const Move& move,
                         const SweptVolumeOptions& options = {});

}  // namespace cwe
