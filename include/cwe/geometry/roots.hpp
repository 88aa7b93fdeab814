#pragma once
// Robust real-root solvers.
//
// Closed forms where they are stable (quadratic without cancellation, a sinφ + b cosφ + c = 0),
// root isolation for cubics and quartics (critical points of the derivative bracket every real
// root; each bracket is solved by Brent's method and Newton-polished), and bracketed scalar
// solvers (Brent root, Brent extremum) with the bracketing strategy of Aras 2008, Algorithm 4.1.
//
// Conventions for every polynomial solver:
//  - coefficients from the highest degree down: solve_quadratic(a, b, c) solves a t² + b t + c;
//  - results are the distinct real roots in ascending order; a double (tangent) root appears
//    once, with `tangent` set for it;
//  - a leading coefficient that is exactly zero lowers the degree; the zero polynomial has no
//    roots and sets `identically_zero` (the caller decides what "everywhere" means for it);
//  - roots are sought in |t| ≤ tol::kRootSearchLimit (1e50): beyond it (a tiny but non-zero
//    leading coefficient) they are not reported.

#include <array>
#include <functional>
#include <optional>

namespace cwe {

// A short list of real roots, ascending. Capacity 4 covers every solver here.
struct Roots {
  std::array<double, 4> value{};
  std::array<bool, 4> tangent{};  // root of even multiplicity: the function touches zero
  int count = 0;
  bool identically_zero = false;

  const double* begin() const { return value.data(); }
  const double* end() const { return value.data() + count; }
  double operator[](int i) const { return value[static_cast<std::size_t>(i)]; }
  int size() const { return count; }
  bool empty() const { return count == 0; }
  void push(double root, bool is_tangent = false);  // keeps the list sorted
};

// a t² + b t + c = 0. Uses q = -(b + sign(b)√Δ)/2, roots q/a and c/q, so neither root suffers
// cancellation. A discriminant within rounding of zero (relative to b² and 4ac) is a double root.
Roots solve_quadratic(double a, double b, double c);

// a sin φ + b cos φ + c = 0 for φ ∈ [0, 2π). Writes a sin φ + b cos φ = ρ sin(φ + δ) with
// ρ = √(a² + b²), δ = atan2(b, a) (Aras 2008 eq. 3.58, 5.25 in one form). No root when
// ρ < |c| (beyond rounding); one tangent root when ρ = |c|; a = b = 0 has no root unless c = 0
// (identically_zero). Roots are Newton-polished.
Roots solve_sin_cos(double a, double b, double c);

// One branch of that closed form, unpolished and unwrapped, given ρ and δ: the root of
// ρ sin(φ + δ) + c = 0 at asin(-c/ρ) - δ (branch 0) or π - asin(-c/ρ) - δ (branch 1). Where no
// root exists (|c| > |ρ|) the branch is continued with the sine clamped to ±1 and `exists` is
// false, so that a curve of roots can be followed past its end (the linear sweep brackets
// crossings with it). ρ ≠ 0.
double sin_cos_branch(double rho, double delta, double c, int branch, bool& exists);

// a t³ + b t² + c t + d = 0.
Roots solve_cubic(double a, double b, double c, double d);

// a t⁴ + b t³ + c t² + d t + e = 0.
Roots solve_quartic(double a, double b, double c, double d, double e);

using ScalarFunction = std::function<double(double)>;

// The root of f in [a, b] by Brent's method. Requires f(a) and f(b) of opposite sign (or one of
// them zero); returns nullopt otherwise. Converges to
// tol::kSolverRelative·|x| + tol::kSolverAbsolute unless `tolerance` is larger.
std::optional<double> brent_root(const ScalarFunction& f, double a, double b,
                                 double tolerance = 0.0);

struct Extremum {
  double x = 0.0;
  double value = 0.0;
};

// The minimum of f on [a, b] by Brent's method (golden section with parabolic steps). For a
// unimodal f it is the global minimum on [a, b]; otherwise a local one. Also compares the end
// points, so a monotone f yields its smaller end.
Extremum brent_minimize(const ScalarFunction& f, double a, double b, double tolerance = 0.0);

// Roots of f on [a, b] for an f with at most one interior extremum (Aras 2008, Algorithm 4.1):
// opposite signs at the ends give one root (Brent); equal signs lead to the extremum c toward
// zero (Brent extremum); if f(c) has the other sign, one root on [a, c] and one on [c, b]
// (Rolle's theorem); if f(c) is zero within `tolerance`, c is a tangent root.
Roots bracketed_roots(const ScalarFunction& f, double a, double b, double tolerance = 0.0);

}  // namespace cwe
