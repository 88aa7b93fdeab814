#pragma once
// One programmed motion of the tool, in the workpiece frame, in millimetres whatever the units of
// the program it came from.
//
// Positions are the tool tip (docs/architecture.md: the programs cwe reads are in tip coordinates),
// axes are unit vectors from the tip towards the shank. A move is parameterised by u ∈ [0, 1]:
//  - line: tip F(u) = start + u (end - start), axis slerped from start_axis to end_axis
//    (a constant axis for 3-axis and 3+2 moves; simultaneous 5-axis otherwise; Aras 2008 §4.2.4);
//  - arc / helix: tip F(u) = center + R(u·sweep)(start - center) + u·axial·normal, with R(θ) the
//    rotation by θ about `normal` (right-hand rule: travel is counter-clockwise seen from the tip
//    of `normal`, so G2 in the XY plane has normal -Z). `sweep` > 0 includes full turns; the axis
//    is slerped like a line's.

#include <string>

#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/vec.hpp"

namespace cwe {

enum class MoveShape { kLine, kArc };
enum class MotionMode { kRapid, kFeed };
enum class SpindleDirection { kStopped, kClockwise, kCounterClockwise };

struct Move {
  MoveShape shape = MoveShape::kLine;
  MotionMode mode = MotionMode::kFeed;
  Vec3 start = Vec3::Zero();
  Vec3 end = Vec3::Zero();
  Vec3 start_axis = Vec3::UnitZ();
  Vec3 end_axis = Vec3::UnitZ();

  // Arcs and helices only.
  Vec3 center = Vec3::Zero();   // centre at the start height: (start - center) ⟂ normal
  Vec3 normal = Vec3::UnitZ();  // unit
  double sweep = 0.0;           // radians, > 0 (2π·k more for k extra full turns)
  double axial = 0.0;           // advance along normal from start to end, mm

  double feed_rate = 0.0;      // mm/min (0 for rapids: the machine's rapid rate)
  double spindle_speed = 0.0;  // rev/min
  SpindleDirection spindle = SpindleDirection::kStopped;
  int tool = 0;    // active tool number (0: none selected)
  int line = 0;    // source line, from 1
  int source = 0;  // index into Toolpath::sources

  bool is_arc() const { return shape == MoveShape::kArc; }
  bool is_rapid() const { return mode == MotionMode::kRapid; }
  // Extra full turns of an arc beyond the first (sweep 2π·k + θ, 0 < θ ≤ 2π, gives k).
  int extra_turns() const;
  double radius() const;  // arc radius, 0 for lines

  Vec3 position(double u) const;
  Vec3 axis(double u) const;     // unit
  Vec3 tangent(double u) const;  // dF/du, mm (zero for a degenerate move)
  // dn/du expressed as ω_u with dn/du = ω_u × n (rad per unit u; zero for a constant axis).
  Vec3 axis_rate(double u) const;
  double length() const;      // arc length of the tip path, mm
  double axis_angle() const;  // angle between start and end axes, rad
  // Box around the tip path: exact for lines and plane arcs; for helices a polygon of ≤ 2°
  // steps grown by its sagitta, so it contains the curve and exceeds it by at most
  // r(1 - cos 1°) ≈ 1.5e-4·r.
  Aabb bounds() const;
  // The part of the move from u0 to u1 (0 ≤ u0 ≤ u1 ≤ 1) as a move of its own: same shape,
  // mode, feed and source, reparameterised so that its u = 0 and 1 are this move's u0 and u1.
  Move part(double u0, double u1) const;
};

// Spherical linear interpolation of unit vectors (the shorter great circle; a fixed
// perpendicular is chosen for antipodal inputs).
Vec3 slerp(const Vec3& a, const Vec3& b, double u);

}  // namespace cwe
