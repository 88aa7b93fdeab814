#pragma once
// The numeric rules of G-code (RS274NGC) input, LinuxCNC's (used by the G-code interpreter only;
// the geometric tolerances are in cwe/geometry/tolerance.hpp).

namespace cwe::tol {

// G-code (RS274NGC) input. These are LinuxCNC 2.9's own values (src/emc/rs274ngc/
// interp_internal.hh, interp_read.cc, interp_check.cc), so that cwe accepts and refuses exactly
// the programs LinuxCNC does; docs/gcode.md says how each was confirmed with LinuxCNC's `rs274`.
// Lengths are in program units (inch under G20, mm under G21), like LinuxCNC's.
//
// Arcs: a centre (or end) closer than this to the start is a zero-radius arc, and an R word may
// fall short of half the chord by this much (RADIUS_TOLERANCE_INCH, and its mm equivalent).
inline constexpr double kGcodeArcRadiusInch = 0.00005;
inline constexpr double kGcodeArcRadiusMm = kGcodeArcRadiusInch * 25.4;
// IJK arcs: the radius to the end may differ from the radius to the start by this much in any
// case, and by up to 100 times as much when also within kGcodeArcSpiralRelative of the radius
// (CENTER_ARC_RADIUS_TOLERANCE_*: end points and centre rounded to 0.001 in or 0.01 mm).
inline constexpr double kGcodeArcSpiralInch = 2 * 0.001 * 1.41421356237309504880;
inline constexpr double kGcodeArcSpiralMm = 2 * 0.01 * 1.41421356237309504880;
inline constexpr double kGcodeArcSpiralRelative = 0.001;
// R arcs: a half chord within this fraction of |R| is taken as exactly |R| (a semicircle;
// LinuxCNC's TINY), so that asin stays defined.
inline constexpr double kGcodeSemicircleRelative = 1e-12;
// Word values that must be whole numbers (M, T, H, L) may differ from one by this much (read as
// that integer); G numbers by this much in tenths (G1.0005 is G1, G1.002 is refused); the P word
// of G2/G3 (number of turns) by this much.
inline constexpr double kGcodeIntegerWord = 1e-4;
inline constexpr double kGcodeGNumberTenths = 1e-3;
inline constexpr double kGcodeArcTurns = 1e-3;
// Two values LinuxCNC compares as equal (TOLERANCE_EQUAL): EQ and NE in expressions, and the
// degenerate triangle of a cutter-compensation entry arc.
inline constexpr double kGcodeEqual = 1e-4;
// Cutter radius compensation (interp_internal.hh TOLERANCE_CONCAVE_CORNER, interp_queue.cc):
// corners between moves whose directions differ by less than this (rad) are tangent, neither
// convex nor concave; a held arc whose end is moved into a concave corner must keep its radius
// within kGcodeCompensatedArcRadii, and may not sweep further than it was programmed to by more
// than the gouge allowance.
inline constexpr double kGcodeConcaveCorner = 0.05;
inline constexpr double kGcodeCompensatedArcRadii = 0.01;
inline constexpr double kGcodeCompensatedArcGougeInch = 0.001;
inline constexpr double kGcodeCompensatedArcGougeMm = 0.0254;

}  // namespace cwe::tol
