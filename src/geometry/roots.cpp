#include "cwe/geometry/roots.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "cwe/core/assert.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/geometry/vec.hpp"
#include "polynomial.hpp"

namespace cwe {

void Roots::push(double root, bool is_tangent) {
  CWE_ASSERT(count < static_cast<int>(value.size()), "Roots holds at most four roots");
  CWE_ASSERT(std::isfinite(root), "roots are finite");
  std::size_t i = static_cast<std::size_t>(count);
  while (i > 0 && value[i - 1] > root) {
    value[i] = value[i - 1];
    tangent[i] = tangent[i - 1];
    --i;
  }
  value[i] = root;
  tangent[i] = is_tangent;
  ++count;
}

namespace {

// Convergence width of the Brent solvers at x: the documented default, or the caller's larger one.
double solver_tolerance(double x, double tolerance) {
  return std::max(tolerance, tol::kSolverRelative * std::abs(x) + tol::kSolverAbsolute);
}

bool same_strict_sign(double a, double b) { return (a > 0.0 && b > 0.0) || (a < 0.0 && b < 0.0); }

// Merges neighbouring roots closer than rounding (a relative gap of kDiscriminantRounding). The
// multiplicities add, so the merged root touches zero (even multiplicity) exactly when both
// parts had the same parity.
Roots merge_close_roots(const Roots& roots) {
  Roots merged;
  merged.identically_zero = roots.identically_zero;
  for (int i = 0; i < roots.size(); ++i) {
    const double root = roots[i];
    const bool tangent = roots.tangent[static_cast<std::size_t>(i)];
    if (merged.count > 0) {
      const std::size_t last = static_cast<std::size_t>(merged.count - 1);
      const double previous = merged.value[last];
      const double scale = std::max(std::abs(previous), std::abs(root));
      if (root - previous <= tol::kDiscriminantRounding * scale) {
        merged.tangent[last] = (merged.tangent[last] == tangent);
        continue;
      }
    }
    merged.push(root, tangent);
  }
  return merged;
}

}  // namespace

namespace detail {

Evaluation evaluate(const Polynomial& polynomial, double t) {
  const int n = polynomial.degree;
  const double abs_t = std::abs(t);
  double value = polynomial.coefficient[0];
  double derivative = 0.0;
  double running = 0.5 * std::abs(value);  // Higham's μ
  double coefficient_error = polynomial.error[0];
  for (int i = 1; i <= n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    derivative = t * derivative + value;
    value = t * value + polynomial.coefficient[k];
    running = abs_t * running + std::abs(value);
    coefficient_error = abs_t * coefficient_error + polynomial.error[k];
  }
  const double rounding = tol::kUnitRoundoff * (2.0 * running - std::abs(value));
  return {value, derivative, std::max(rounding, 0.0) + coefficient_error};
}

namespace {

double value_at(const Polynomial& polynomial, double t) {
  double value = polynomial.coefficient[0];
  for (int i = 1; i <= polynomial.degree; ++i) {
    value = t * value + polynomial.coefficient[static_cast<std::size_t>(i)];
  }
  return value;
}

// Newton steps from a bracketed root, each kept only if it stays in [lo, hi] and lowers |p|.
double newton_polish(const Polynomial& polynomial, double root, double lo, double hi) {
  constexpr int kPolishSteps = 4;
  Evaluation current = evaluate(polynomial, root);
  for (int step = 0; step < kPolishSteps; ++step) {
    if (current.value == 0.0 || current.derivative == 0.0) break;  // exact, or flat: stop
    const double next = root - current.value / current.derivative;
    if (!(next >= lo && next <= hi) || next == root) break;
    const Evaluation candidate = evaluate(polynomial, next);
    if (std::abs(candidate.value) >= std::abs(current.value)) break;
    root = next;
    current = candidate;
  }
  return root;
}

// Roots beyond kRootSearchLimit (a tiny leading coefficient sends one toward infinity, possibly
// past the range of doubles) are not reported, as in the isolation below.
void push_in_range(Roots& roots, double root, bool tangent = false) {
  if (std::abs(root) <= tol::kRootSearchLimit) roots.push(root, tangent);
}

// The solvers below take a non-zero leading coefficient and coefficients scaled to a largest
// magnitude in [1, 2).
Roots solve_linear(const Polynomial& p) {
  Roots roots;
  push_in_range(roots, -p.coefficient[1] / p.coefficient[0]);
  return roots;
}

// Quadratic without cancellation: q = -(b + sign(b)√Δ)/2, roots q/a and c/q. A discriminant
// within its rounding (of b² - 4ac, plus the first-order effect of the coefficient errors) is a
// double root.
Roots solve_quadratic_scaled(const Polynomial& p) {
  const double a = p.coefficient[0];
  const double b = p.coefficient[1];
  const double c = p.coefficient[2];
  const double discriminant = b * b - 4.0 * a * c;
  const double allowance = tol::kDiscriminantRounding * (b * b + 4.0 * std::abs(a * c)) +
                           2.0 * std::abs(b) * p.error[1] + 4.0 * std::abs(a) * p.error[2] +
                           4.0 * std::abs(c) * p.error[0];
  Roots roots;
  if (std::abs(discriminant) <= allowance) {
    // Tangent: a double root (a ≠ 0 here).
    push_in_range(roots, -b / (2.0 * a), true);
    return roots;
  }
  if (discriminant < 0.0) return roots;  // complex pair
  // discriminant > allowance ≥ 0, so q ≠ 0.
  const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
  push_in_range(roots, q / a);
  push_in_range(roots, c / q);
  return roots;
}

// Cauchy's bound: every root satisfies |t| < 1 + max |c_i / c_0|, clamped to kRootSearchLimit.
double cauchy_bound(const Polynomial& p) {
  double largest = 0.0;
  for (int i = 1; i <= p.degree; ++i) {
    largest = std::max(largest, std::abs(p.coefficient[static_cast<std::size_t>(i)]));
  }
  const double leading = std::abs(p.coefficient[0]);
  // largest ≤ 2 and leading > 0 after scaling; guard the ratio against overflow explicitly.
  if (largest >= leading * tol::kRootSearchLimit) return tol::kRootSearchLimit;
  return std::min(1.0 + largest / leading, tol::kRootSearchLimit);
}

// Cubic and quartic by real-root isolation: the critical points (real roots of the derivative,
// solved recursively) split [-bound, bound] into monotone brackets. A bracket whose ends have
// opposite signs holds one simple root (Brent, then Newton). A critical point whose value is
// within the evaluation's error bound is a root itself; it touches zero (even multiplicity,
// `tangent`) when the nearest non-zero values on either side have the same sign.
Roots solve_by_isolation(const Polynomial& p) {
  const int n = p.degree;
  Polynomial derivative;
  derivative.degree = n - 1;
  for (int i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const double factor = static_cast<double>(n - i);
    derivative.coefficient[k] = factor * p.coefficient[k];
    derivative.error[k] =
        factor * p.error[k] + tol::kUnitRoundoff * std::abs(derivative.coefficient[k]);
  }
  const Roots critical = solve(derivative);

  const double bound = cauchy_bound(p);
  std::array<double, 6> point{};
  std::array<int, 6> sign{};
  int count = 0;
  point[static_cast<std::size_t>(count++)] = -bound;
  for (const double c : critical) {
    if (c > -bound && c < bound) point[static_cast<std::size_t>(count++)] = c;
  }
  point[static_cast<std::size_t>(count++)] = bound;
  for (int i = 0; i < count; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const Evaluation e = evaluate(p, point[k]);
    if (std::abs(e.value) <= e.error_bound) {
      sign[k] = 0;  // zero within rounding: a root at this critical point
    } else {
      sign[k] = e.value > 0.0 ? 1 : -1;
    }
  }

  Roots roots;
  for (int i = 0; i < count; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (sign[k] != 0) continue;
    int left = 0;
    for (int j = i - 1; j >= 0 && left == 0; --j) left = sign[static_cast<std::size_t>(j)];
    int right = 0;
    for (int j = i + 1; j < count && right == 0; ++j) right = sign[static_cast<std::size_t>(j)];
    roots.push(point[k], left != 0 && left == right);
  }
  const auto f = [&p](double t) { return value_at(p, t); };
  for (int i = 0; i + 1 < count; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (sign[k] * sign[k + 1] >= 0) continue;  // no sign change, or an end is a root already
    const std::optional<double> root = brent_root(f, point[k], point[k + 1]);
    CWE_ASSERT(root.has_value(), "a sign change brackets a root");
    roots.push(newton_polish(p, *root, point[k], point[k + 1]));
  }
  return merge_close_roots(roots);
}

}  // namespace

Roots solve(Polynomial p) {
  CWE_ASSERT(p.degree >= 0 && p.degree <= 4, "degree at most 4");
  for (std::size_t k = 0; k <= static_cast<std::size_t>(p.degree); ++k) {
    CWE_ASSERT(std::isfinite(p.coefficient[k]) && std::isfinite(p.error[k]),
               "polynomial coefficients must be finite");
  }
  // An exactly zero leading coefficient lowers the degree.
  while (p.degree > 0 && p.coefficient[0] == 0.0) {
    for (int i = 0; i < p.degree; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      p.coefficient[k] = p.coefficient[k + 1];
      p.error[k] = p.error[k + 1];
    }
    p.coefficient[static_cast<std::size_t>(p.degree)] = 0.0;
    p.error[static_cast<std::size_t>(p.degree)] = 0.0;
    --p.degree;
  }
  Roots roots;
  if (p.degree == 0) {
    // A constant: no root, or the zero polynomial (every t is a root; the caller decides).
    roots.identically_zero = (p.coefficient[0] == 0.0);
    return roots;
  }
  // Scale by a power of two (exact) so the largest coefficient lies in [1, 2): no overflow in
  // b², no underflow of the error bounds, and the roots are unchanged.
  double largest = 0.0;
  for (int i = 0; i <= p.degree; ++i) {
    largest = std::max(largest, std::abs(p.coefficient[static_cast<std::size_t>(i)]));
  }
  const int exponent = std::ilogb(largest);
  for (int i = 0; i <= p.degree; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    p.coefficient[k] = std::ldexp(p.coefficient[k], -exponent);
    p.error[k] = std::ldexp(p.error[k], -exponent);
  }
  switch (p.degree) {
    case 1:
      return solve_linear(p);
    case 2:
      return solve_quadratic_scaled(p);
    default:
      CWE_ASSERT(p.degree <= 4, "degree at most 4");
      return solve_by_isolation(p);
  }
}

}  // namespace detail

Roots solve_quadratic(double a, double b, double c) {
  detail::Polynomial p;
  p.degree = 2;
  p.coefficient = {a, b, c, 0.0, 0.0};
  return detail::solve(p);
}

Roots solve_cubic(double a, double b, double c, double d) {
  detail::Polynomial p;
  p.degree = 3;
  p.coefficient = {a, b, c, d, 0.0};
  return detail::solve(p);
}

Roots solve_quartic(double a, double b, double c, double d, double e) {
  detail::Polynomial p;
  p.degree = 4;
  p.coefficient = {a, b, c, d, e};
  return detail::solve(p);
}

namespace {

// φ reduced to [0, 2π).
double wrap_angle(double phi) {
  double wrapped = std::fmod(phi, kTwoPi);
  if (wrapped < 0.0) wrapped += kTwoPi;
  // Adding kTwoPi to a tiny negative value rounds to kTwoPi itself: that is angle 0.
  if (wrapped >= kTwoPi) wrapped = 0.0;
  return wrapped;
}

// Newton steps on g(φ) = a sin φ + b cos φ + c, each kept only if it lowers |g|.
double polish_sin_cos(double a, double b, double c, double phi) {
  constexpr int kPolishSteps = 4;
  const auto g = [&](double x) { return a * std::sin(x) + b * std::cos(x) + c; };
  double value = g(phi);
  for (int step = 0; step < kPolishSteps; ++step) {
    const double slope = a * std::cos(phi) - b * std::sin(phi);
    if (value == 0.0 || slope == 0.0) break;
    const double next = phi - value / slope;
    const double next_value = g(next);
    if (!(std::abs(next_value) < std::abs(value))) break;
    phi = next;
    value = next_value;
  }
  return phi;
}

}  // namespace

Roots solve_sin_cos(double a, double b, double c) {
  Roots roots;
  if (a == 0.0 && b == 0.0) {
    // No φ dependence: the equation is c = 0, for every φ or for none.
    roots.identically_zero = (c == 0.0);
    return roots;
  }
  // a sin φ + b cos φ = ρ sin(φ + δ) (Aras 2008, eq. 3.58 / 5.25).
  const double rho = std::hypot(a, b);
  const double delta = std::atan2(b, a);
  const double gap = rho - std::abs(c);
  if (std::abs(gap) <= tol::kDiscriminantRounding * (rho + std::abs(c))) {
    // Tangent: ρ = |c| within rounding, sin(φ + δ) = -sign(c), one double root.
    const double phi = (c > 0.0 ? -0.5 * kPi : 0.5 * kPi) - delta;
    roots.push(wrap_angle(phi), true);
    return roots;
  }
  if (gap < 0.0) return roots;           // |c| > ρ: no root
  bool exists = true;  // |c/ρ| < 1 here
  const double first = wrap_angle(polish_sin_cos(a, b, c, sin_cos_branch(rho, delta, c, 0, exists)));
  const double second =
      wrap_angle(polish_sin_cos(a, b, c, sin_cos_branch(rho, delta, c, 1, exists)));
  roots.push(first);
  if (second != first) roots.push(second);
  return roots;
}

double sin_cos_branch(double rho, double delta, double c, int branch, bool& exists) {
  double s = -c / rho;
  exists = s >= -1.0 && s <= 1.0;
  s = std::clamp(s, -1.0, 1.0);
  const double base = std::asin(s);
  return (branch == 0 ? base : kPi - base) - delta;
}

std::optional<double> brent_root(const ScalarFunction& f, double a, double b, double tolerance) {
  double fa = f(a);
  double fb = f(b);
  if (fa == 0.0) return a;
  if (fb == 0.0) return b;
  if (same_strict_sign(fa, fb)) return std::nullopt;  // not a bracket
  // Brent 1973, ch. 4 (zeroin), as in Numerical Recipes' zbrent: b is the best estimate, c the
  // contrapoint with f(c) of the other sign, a the previous b.
  double c = b;
  double fc = fb;
  double d = b - a;
  double e = d;
  for (int iteration = 0; iteration < tol::kSolverMaxIterations; ++iteration) {
    if (same_strict_sign(fb, fc)) {
      c = a;
      fc = fa;
      d = b - a;
      e = d;
    }
    if (std::abs(fc) < std::abs(fb)) {
      a = b;
      b = c;
      c = a;
      fa = fb;
      fb = fc;
      fc = fa;
    }
    const double half_tolerance = 0.5 * solver_tolerance(b, tolerance);
    const double middle = 0.5 * (c - b);
    if (std::abs(middle) <= half_tolerance || fb == 0.0) return b;
    bool interpolated = false;
    if (std::abs(e) >= half_tolerance && std::abs(fa) > std::abs(fb)) {
      // Secant (a == c) or inverse quadratic interpolation. |fa| > |fb| ≥ 0 and |fc| ≥ |fb| > 0.
      const double s = fb / fa;
      double p = 0.0;
      double q = 0.0;
      if (a == c) {
        p = 2.0 * middle * s;
        q = 1.0 - s;
      } else {
        const double qa = fa / fc;
        const double r = fb / fc;
        p = s * (2.0 * middle * qa * (qa - r) - (b - a) * (r - 1.0));
        q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
      }
      if (p > 0.0) q = -q;
      p = std::abs(p);
      // Extreme function values can overflow the interpolation: bisect then.
      if (std::isfinite(p) && std::isfinite(q)) {
        const double limit1 = 3.0 * middle * q - std::abs(half_tolerance * q);
        const double limit2 = std::abs(e * q);
        if (2.0 * p < std::min(limit1, limit2)) {  // q ≠ 0 here, since the limits are then > 0
          e = d;
          d = p / q;
          interpolated = true;
        }
      }
    }
    if (!interpolated) {
      d = middle;  // bisection
      e = d;
    }
    a = b;
    fa = fb;
    b += std::abs(d) > half_tolerance ? d : std::copysign(half_tolerance, middle);
    fb = f(b);
  }
  return b;
}

Extremum brent_minimize(const ScalarFunction& f, double a, double b, double tolerance) {
  if (a > b) std::swap(a, b);
  // Brent 1973, ch. 5 (localmin): golden section with parabolic steps. x is the best point so
  // far, w the second best, v the previous w; e the step before last.
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));
  double lo = a;
  double hi = b;
  double x = lo + golden * (hi - lo);
  double w = x;
  double v = x;
  double fx = f(x);
  double fw = fx;
  double fv = fx;
  double d = 0.0;
  double e = 0.0;
  for (int iteration = 0; iteration < tol::kSolverMaxIterations; ++iteration) {
    const double middle = 0.5 * (lo + hi);
    const double step_tolerance = 0.5 * solver_tolerance(x, tolerance);
    const double twice_tolerance = 2.0 * step_tolerance;
    if (std::abs(x - middle) <= twice_tolerance - 0.5 * (hi - lo)) break;
    bool parabolic = false;
    if (std::abs(e) > step_tolerance) {
      double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      r = e;
      // Accept the parabola's vertex if it lies inside and the step is less than half the step
      // before last (q = 0 fails the first test, so p / q is safe).
      if (std::isfinite(p) && std::isfinite(q) && std::abs(p) < std::abs(0.5 * q * r) &&
          p > q * (lo - x) && p < q * (hi - x)) {
        e = d;
        d = p / q;
        const double u = x + d;
        if (u - lo < twice_tolerance || hi - u < twice_tolerance) {
          d = x < middle ? step_tolerance : -step_tolerance;
        }
        parabolic = true;
      }
    }
    if (!parabolic) {
      e = (x < middle ? hi : lo) - x;
      d = golden * e;
    }
    const double u = x + (std::abs(d) >= step_tolerance ? d : std::copysign(step_tolerance, d));
    const double fu = f(u);
    if (fu <= fx) {
      if (u < x) {
        hi = x;
      } else {
        lo = x;
      }
      v = w;
      fv = fw;
      w = x;
      fw = fx;
      x = u;
      fx = fu;
    } else {
      if (u < x) {
        lo = u;
      } else {
        hi = u;
      }
      if (fu <= fw || w == x) {
        v = w;
        fv = fw;
        w = u;
        fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u;
        fv = fu;
      }
    }
  }
  // The interior search finds a local minimum; a monotone f has its minimum at an end.
  Extremum best{x, fx};
  const double fa = f(a);
  if (fa < best.value) best = {a, fa};
  const double fb = f(b);
  if (fb < best.value) best = {b, fb};
  return best;
}

Roots bracketed_roots(const ScalarFunction& f, double a, double b, double tolerance) {
  if (a > b) std::swap(a, b);
  // Aras 2008, Algorithm 4.1. `tolerance` is the zero test for f at the extremum; the Brent
  // steps use their default (x) tolerance.
  const double fa = f(a);
  const double fb = f(b);
  Roots roots;
  const auto push_unique = [&roots](double root, bool tangent) {
    for (const double existing : roots) {
      if (existing == root) return;
    }
    roots.push(root, tangent);
  };
  if ((fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0)) {
    // Opposite signs: with at most one extremum, exactly one crossing.
    push_unique(*brent_root(f, a, b), false);
    return roots;
  }
  if (fa == 0.0) push_unique(a, false);
  if (fb == 0.0) push_unique(b, false);
  // Equal signs (or a zero end): the extremum toward zero decides. Its direction comes from the
  // non-zero end; with both ends zero, the one-extremum f has no other root.
  const double reference = fa != 0.0 ? fa : fb;
  if (reference == 0.0) return roots;
  const double direction = reference > 0.0 ? 1.0 : -1.0;  // minimise f, or maximise it
  const Extremum extremum =
      brent_minimize([&f, direction](double x) { return direction * f(x); }, a, b);
  const double c = extremum.x;
  const double fc = direction * extremum.value;
  if (c == a || c == b) return roots;  // monotone toward zero: no interior extremum
  if (std::abs(fc) <= tolerance) {
    // The extremum touches zero: a tangent (double) root.
    push_unique(c, true);
    return roots;
  }
  if (fc * direction < 0.0) {
    // The extremum crosses zero: one root on each side (Rolle's theorem).
    push_unique(*brent_root(f, a, c), false);
    push_unique(*brent_root(f, c, b), false);
  }
  return roots;
}

}  // namespace cwe
