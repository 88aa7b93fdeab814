#pragma once
// Engagement maps from the tri-dexel workpiece (docs/engagement.md).
//
// Definition (Aras 2008 §6.1, eq. 6.1–6.5): CWE = FCS ∩ (W ∩ SV). A point P of the cutter surface
// at a cutter location is engaged when it moves into the material (f = N·V > 0, grazing points
// excluded) and the motion from this location on removes material right there: the step that
// follows the location (its swept volume SV, removed from the workpiece W as it stands) takes
// material within `contact` of P. The step's removal is read as dexel segments (RemovalRecord),
// so a wall or floor that earlier passes left exactly where this motion's envelope runs (a step-
// down along the same path, a pass repeated, a tool edge running along a stock face) is
// recognised as already cut: nothing is removed there but float rounding of the ray ends, which
// the test ignores (stretches shorter than two float spacings of the stock's coordinates).
//
// Method: the cutter surface is gridded in φ (cells of `phi_step`) × axial discs (side) or
// rings (flat bottom) of `disc_height`. For a cell centre P with outward normal N and f > 0, the
// ray most nearly along N that passes within s/√2 of P meets P's tangent plane at Q; P is
// engaged when the step removed a stretch of that ray overlapping the window from just inside
// the cutter surface (the surface lies inside its tangent plane by up to ¾κs² within that
// reach, κ its largest curvature) to `contact` outside it. Runs of engaged cells become φ
// intervals whose ends are refined by bisection on the same test, so an angle is located to the
// ray grid's resolution (Q lies within s√(3/2) of P), not to the cell size.
//
// The one tolerance, `contact` (default: the sweep tolerance of the simulation, s/10): how far
// from the cutter surface removed material still counts as touching it. It covers the gap
// between the tool at a cutter location and the end of the previous step's sweep (zero for
// linear 3-axis and 3+2 moves and arcs, up to the sweep tolerance for 5-axis moves, whose pieces
// turn about their mean axis), and is far below any real chip (feeds per tooth are 0.02–0.3 mm),
// so material the step reaches only later in the step (the cutter approaching a face) is not
// engaged yet.
//
// Accuracy: boundaries of the engaged region are placed within about s/√2 on the cutter surface
// (an angle error of about s/(√2 ρ) at radius ρ, a depth error within s). At a grazing line of
// fresh material (φ = 0° or 180° of a slot) the removed layer thins as ρ(1 - cos φ); it is seen
// down to twice the float rounding, about 0.2° for ρ = 5 mm on a 100 mm stock.
//
// Cost: per cutter location, the discs and rings whose circle comes within reach of the step's
// removal box are scanned; f is evaluated for every cell of those, the removal record (a binary
// search per ray) only where f > 0 and the cell's point is within that reach. A side disc of an
// upright tool's cylindrical part whose rays lost in the step what the last scanned disc's rays
// lost, with the same front, takes that disc's intervals unscanned (exact: every cell's test
// would find what it found; DexelEngagement::reuse_of).

#include "cwe/engagement/engagement_grid.hpp"
#include "cwe/engagement/engagement_map.hpp"
#include "cwe/kinematics/tool_state.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/workpiece/dexel/removal_record.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"

namespace cwe {

class DexelEngagement {
 public:
  // The grid for `cutter` on a workpiece of ray spacing `spacing`. Throws InputError for a
  // non-positive spacing or option.
  DexelEngagement(const Cutter& cutter, double spacing, const EngagementOptions& options = {});

  // The engagement of the cutter in `state` (tool frame and velocities) with `stock`, where
  // `step` records what the step of motion that starts in `state` removed from `stock`
  // (TriDexel::remove with a record; the stock may be read before or after that removal).
  EngagementMap at(const TriDexel& stock, const RemovalRecord& step, const ToolState& state) const;

  double disc_height() const { return grid_.disc_height(); }
  double contact() const { return contact_; }
  double phi_step() const { return grid_.phi_step(); }
  int phi_cells() const { return grid_.phi_cells(); }

 private:
  using Band = EngagementGrid::Band;
  // What decides a side disc's intervals besides its rays' stretches, for a disc of an upright
  // tool's cylindrical part whose rays lie within the flutes (band null for any other band).
  struct Reuse {
    const Band* band = nullptr;
    EngagementGrid::Front front;
    int level = 0;  // the height index of the X and Y rays its cells read
    // Whether this disc's intervals are those of disc `was` (both with a band) in `step`.
    bool same(const Reuse& was, const RemovalRecord& step) const;
  };
  Reuse reuse_of(const TriDexel& stock, const ToolState& state, const Band& band,
                 const EngagementGrid::Front& front) const;
  // The last disc of a location scanned that another may reuse, with its intervals.
  struct Scanned {
    Reuse reuse;
    std::vector<Interval> found;
  };
  // Engaged φ intervals of one band; `last` is the previous disc of the location that could be
  // reused, kept up to date.
  std::vector<Interval> scan(const TriDexel& stock, const RemovalRecord& step,
                             const ToolState& state, const Band& band, const Vec3& v_tcs,
                             const Vec3& w_tcs, Scanned& last) const;

  // How far scan()'s first test grows a step's box (its `near`) for a band whose surface
  // departs `departure` from its tangent plane.
  double margin(double departure) const;
  // The discs [first, end) whose circles an upright tool at `state` can have within a step's
  // box: for every other disc scan() returns at its first test. All discs for any other tool.
  std::array<std::size_t, 2> discs_near(const RemovalRecord& step, const ToolState& state) const;

  EngagementGrid grid_;
  double spacing_;
  double contact_;
  bool skip_far_cells_;
  bool skip_far_discs_;
  bool reuse_alike_discs_;
  double most_departure_ = 0.0;  // the largest departure of a disc
};

}  // namespace cwe
