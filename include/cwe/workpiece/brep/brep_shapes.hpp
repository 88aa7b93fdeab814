#pragma once
// Exact solids of cutters and of the volumes they sweep, as OpenCASCADE shapes: what the B-rep
// workpiece removes (Aras 2008 §6.1). For code that works on the shapes (the B-rep workpiece,
// its tests); the rest of cwe sees BrepStock only.
//
// A linear move with a constant axis sweeps the Minkowski sum of the convex tool T and the
// segment d = end − start (Aras 2008 §4.2, built as §6.1 does): the faces of T that trail (the
// outward normal n has n·d < 0) kept at the start, the faces that lead kept at the end, and the
// silhouette between them (the grazing curve, n·d = 0) swept along d, sewn into one solid. The
// silhouette is cut into T's faces by planes that hold it:
//  - a cylinder's two rulings lie in the plane through the axis square to d's horizontal part
//    (which also halves a disc that a level move runs along: its trailing half stays at the
//    start, its leading half goes to the end, and the diameter between them sweeps the floor);
//  - a sphere's great circle in the plane through its centre square to d;
//  - a cone's two rulings (cos θ = −n_z d_z / (n_ρ |d_h|)) meet at its apex: the plane through
//    the apex and both;
//  - where the normal jumps (a flat bottom's rim, a chamfer's top, the top disc) the silhouette
//    runs along the joint circle, an edge T already has;
//  - a torus (a bull-nose corner): the plane through the axis when d is square to the axis,
//    the equator's plane when d is along it. Along a ramp its silhouette is no plane curve
//    (tan ψ = −(|d_h|/d_z)·cos(θ − β)): a sheet ruled by horizontal segments through it, whose
//    guide curves interpolate it, cuts it there.
// Under a plunge the flank that d runs along is kept at the start, and the rim below it swept.

#include <BRepAlgoAPI_BooleanOperation.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Solid.hxx>

#include <vector>

#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/vec.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/move.hpp"
#include "cwe/workpiece/brep/brep_stock.hpp"

namespace cwe {

// The cutter's solid (its profile revolved about its axis, closed by the top disc) with its tip
// at `tip` and its axis along unit `axis` (the frame of cwe's faceted tools: x as close to world
// X as the axis allows). Throws InputError for a profile with a concave part.
TopoDS_Solid tool_solid(const Cutter& cutter, const Vec3& tip, const Vec3& axis);

// The volume the cutter sweeps from tip `start` to tip `end` with unit `axis`, exact (see
// above): the tool at `start` when the two coincide. Throws ComputationError when OpenCASCADE
// cannot build it, or when the solid's volume is not the one the motion sweeps.
TopoDS_Shape linear_sweep_solid(const Cutter& cutter, const Vec3& start, const Vec3& end,
                                const Vec3& axis);

// The volume the cutter sweeps along a planar arc (no advance along its normal) with its axis
// along the arc's normal, as solids whose union it is. Off the arc's axis it is one solid, sewn
// like a line's, the tool's faces cut by the plane through both axes (where the silhouette lies)
// and the silhouette revolved. A full circle is the tool's section by that plane revolved into a
// ring. Round a corner (the tool over the arc's axis) it is three: the section clamped at the
// axis and revolved through the arc's angle, and the tool at both ends (the points of the sweep
// outside the arc's angles are nearest one of them); they are cut one after the other, never
// fused (OpenCASCADE's union of a bull-nose's pieces, whose tori touch along the end sections,
// came out valid and a third short). Throws ComputationError when OpenCASCADE cannot build them,
// or when a swept or revolved solid's volume is not the one planar_arc_swept_volume gives it.
std::vector<TopoDS_Shape> planar_arc_sweep_solids(const Cutter& cutter, const Move& arc);

// The volume the cutter sweeps along a helix (an arc that advances along its normal) with its
// axis along the helix's, in pieces of at most half a turn (no piece comes back over itself),
// each sewn like a line's: under a screw about an axis parallel to the tool's, n·v(p) on the
// whole tool is n·(the tool axis's velocity), so the silhouette is the one of a line along that
// velocity; it is swept by a pipe shell along the tip's helix with the axis as fixed binormal
// (the screw motion), and each piece's volume is the line's of length α·√(R² + a²) (a the rise
// per radian). Over more than a turn, only the turn at the helix's low end is swept, each of its
// poses with the tool lengthened to the top of the poses whole turns over it: for a convex tool
// ending in a straight side at least one pitch tall, exactly the same union, without a turn's
// floor under the one before (which OpenCASCADE's cuts refused). Throws ComputationError for a
// helix not wider than the tool, or when OpenCASCADE cannot build a piece.
std::vector<TopoDS_Shape> helix_sweep_solids(const Cutter& cutter, const Move& helix);

// The volume the cutter sweeps in a tilt in place: a line whose tip stays still while the axis
// turns from the start axis to the end axis (slerp: about the line L through the tip square to
// both). Exact, as six solids: the tool at both ends, the two halves of its meridian section in
// the plane of the start axis and L revolved about L through the turn, and the two halves of its
// top disc (either side of the diameter along L) revolved likewise. About L, a tool whose radius
// never narrows towards its top meets each circle round L within its height of L in one arc through
// that plane, and each circle farther out in two arcs that start at the top disc; so the revolved
// section and disc join each arc at the start to the same arc at the end. Throws ComputationError
// for a profile that narrows towards its top (the argument fails there), for a move that does not
// tilt in place, or when OpenCASCADE cannot build a solid.
std::vector<TopoDS_Shape> tilt_sweep_solids(const Cutter& cutter, const Move& move);

// The volume the cutter sweeps along a line whose axis turns (a simultaneous 5-axis move),
// lofted (Aras 2008 builds the envelope from its grazing curves): at poses evenly spaced along
// the move, the tool's faces are cut along the grazing curve of the motion at that instant
// (f = N·(v + ω × p) = 0: planes on a ball and on discs, sheets through the curve on cylinders,
// cones and tori; where a piece's curve leaves it part-way, a line's silhouette), and those
// curves are lofted (BRepOffsetAPI_ThruSections) into the band sewn between the trailing faces
// at the start and the leading faces at the end. The deviation is measured on the solid's faces
// where they lie inside `within` (the stock's box: beyond it a deviation changes no cut), as the
// largest distance to the boundary of the union of the tool's poses; poses are doubled from 5
// up to 17 until it is within `tolerance`. A piece whose curve stops part-way, at a fold where
// its two roots meet (a bull-nose's corner as the tool descends while it tilts), is cut by one
// sheet out along one root and back along the other. Throws ComputationError when the curve
// changes its kind of edges along the move (a ball end whose lean turns from forward to back),
// when OpenCASCADE cannot build the solid, or when it stays off by more than the tolerance.
struct LoftedSweep {
  std::vector<TopoDS_Shape> solids;  // one for a whole loft; parts in order, see below
  int sections = 0;                  // intervals between the poses lofted, over all parts
  double deviation = 0.0;            // mm, measured as above (the largest part's)
  int changes = 0;                   // where the move was split (lofted_sweep_parts)
};
LoftedSweep lofted_sweep_solid(const Cutter& cutter, const Move& move, double tolerance,
                               const Aabb& within);
// The same for a move whose grazing curve changes its kind of edges: the changes are found
// between 17 poses and bisected from both sides (a pose right at a change, whose cuts leave a
// sliver face no test can sort, counts as neither) down to brackets so short that no point of
// the tool moves farther than `tolerance` across one (two changes closer than that share one);
// each part between them is lofted, and each bracket is covered by the tool at its middle pose
// (or at the middles of as many stretches of that width), within half the tolerance. The solids
// are the parts and the tools between them, in order. Throws ComputationError as
// lofted_sweep_solid, when a part still changes its kind (two changes between two of the 17
// poses), and when poses no test can sort cover more than 16 brackets.
LoftedSweep lofted_sweep_parts(const Cutter& cutter, const Move& move, double tolerance,
                               const Aabb& within);

// Volume of a shape, mm³ (BRepGProp), with each planar face of several wires (a stock's top with
// the openings of pockets and slots) integrated wire by wire: its outer wire's face less each
// hole's face. BRepGProp's integral over the whole face came out 0.256 mm² short on the CATIA
// contour's top face after its tilted slot (docs/brep.md), whose opening's wire has a gap of
// 0.0033 mm closed by a vertex's tolerance, and so the stock's volume 0.785 mm³ short until a
// later cut rebuilt that face and the stock seemed to grow. Each wire alone integrates right.
double shape_volume(const TopoDS_Shape& shape);

// Runs a boolean of `argument` (the stock) and one tool, in this thread, with the fuzzy value if
// positive, leaving both as they were (OpenCASCADE's non-destructive mode).
void run_boolean(BRepAlgoAPI_BooleanOperation& op, const TopoDS_Shape& argument,
                 const TopoDS_Shape& tool, double fuzzy);

// `shape` mended by OpenCASCADE's ShapeFix_Shape, built on a copy: ShapeFix changes the edges
// and faces it fixes in place (their tolerances, flags and curves), and those of the stock are
// shared with the stock kept where every attempt on the mended one is refused.
TopoDS_Shape mended_copy(const TopoDS_Shape& shape);

struct BrepStock::Solid {
  TopoDS_Shape shape;
};

// The stock as the solids of `shape` (a STEP file's, checked by StepModel).
BrepStock brep_stock(const TopoDS_Shape& shape);

}  // namespace cwe
