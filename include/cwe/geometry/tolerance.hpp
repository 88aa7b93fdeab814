#pragma once
// The tolerances cwe's modules share, with their scale. No file holds a bare epsilon: one used by
// a single algorithm is a named constant beside it, with its scale (G-code's numeric rules are in
// src/toolpath/gcode_tolerance.hpp).
//
// Units are millimetres and radians. Models are parts up to about a metre (kModelScale), where a
// double resolves about 2e-13 mm; cwe's geometric tolerances sit many orders above that rounding
// and many orders below any machining resolution (1e-3 mm).

namespace cwe::tol {

// Size of the largest model cwe is meant for, in millimetres.
inline constexpr double kModelScale = 1000.0;

// Relative epsilon for floating-point comparisons: multiply by the size of the operands
// (`kRelative * scale`). About 4500 ulps of 1.0.
inline constexpr double kRelative = 1e-12;

// Two computed points closer than this are the same point (mm): 1e-9 of kModelScale.
inline constexpr double kLength = 1e-6;

// Dimensions a user or a CAM system wrote (tool parameters, profile end points) agree when they
// differ by less than this (mm). CAM output commonly carries 4 decimals, so 1e-4 mm of rounding
// must be accepted; anything larger is a real inconsistency.
inline constexpr double kInputLength = 2e-4;

// Two directions closer than this are the same direction (rad).
inline constexpr double kAngle = 1e-9;

// Angles a user wrote agree when they differ by less than this (rad): 1e-4 degree.
inline constexpr double kInputAngle = 1e-4 * 3.14159265358979323846 / 180.0;

// Iterative solvers (Brent root and extremum) stop when the bracket is below
// kSolverRelative * |x| + kSolverAbsolute, or after kSolverMaxIterations.
inline constexpr double kSolverRelative = 4e-16;
inline constexpr double kSolverAbsolute = 1e-15;
inline constexpr int kSolverMaxIterations = 200;

// Unit roundoff u = 2⁻⁵³ ≈ 1.1e-16 of a double: one correctly rounded operation errs by at most
// u relative. Rounding-error bounds (Horner's running error, discriminants) are multiples of it.
inline constexpr double kUnitRoundoff = 0x1p-53;

// A discriminant b² − 4ac of exact coefficients is within rounding of zero when
// |Δ| ≤ kDiscriminantRounding · (b² + 4|ac|): the two products and the subtraction err by at
// most 2u(b² + 4|ac|) together; this is twice that.
inline constexpr double kDiscriminantRounding = 4 * kUnitRoundoff;

// Relative rounding of a quantity that cwe formed from coordinates in a few operations
// (differences, dot products, squares; each step ≤ a few u of the magnitudes involved): about
// 7e-15 of the magnitudes it was formed from. Intersectors judge tangency against it, so a
// tangent ray never loses its contact to rounding; a secant chord shorter than about
// 2·√(7e-15)·size ≈ 2e-7·size may then be reported as a point.
inline constexpr double kGeometricRounding = 64 * kUnitRoundoff;

// Polynomial solvers look for roots in |t| ≤ kRootSearchLimit (the Cauchy bound, clamped), far
// beyond any parameter cwe uses (models are ~1e3 mm) and small enough that a quartic evaluated
// there stays finite (t⁴ = 1e200).
inline constexpr double kRootSearchLimit = 1e50;

// A direction a user or a CAM system wrote (a tool axis, a circle normal) is normalised after
// reading; one shorter than this is a zero vector plus rounding, not a direction (dimensionless).
// CAM systems write unit vectors to 4 to 7 decimals, so a real direction is never near it.
inline constexpr double kInputDirection = 1e-3;

}  // namespace cwe::tol
