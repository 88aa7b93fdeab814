#pragma once
// Private to the geometry module: real polynomials of degree ≤ 4 that carry an absolute error
// bound for each coefficient, and the root isolation behind solve_quadratic, solve_cubic and
// solve_quartic.
//
// The public solvers take their coefficients as exact (zero error). The intersectors form
// coefficients from coordinates, with cancellation; they pass an error bound for each coefficient
// so that a tangent (double) root is recognised against the real uncertainty of the data, not
// only against the rounding of the evaluation.

#include <array>

#include "cwe/geometry/roots.hpp"

namespace cwe::detail {

struct Polynomial {
  int degree = 0;
  // coefficient[i] multiplies t^(degree - i): coefficient[0] is the leading one.
  std::array<double, 5> coefficient{};
  // Absolute error bound of coefficient[i] (0 for exact coefficients).
  std::array<double, 5> error{};
};

struct Evaluation {
  double value = 0.0;
  double derivative = 0.0;
  // Bound on |computed value - exact value of the exact polynomial|: Horner's running error
  // (Higham 2002, Algorithm 5.1) plus the coefficient errors Σ error[i]·|t|^(degree - i).
  double error_bound = 0.0;
};

Evaluation evaluate(const Polynomial& polynomial, double t);

// Distinct real roots, ascending, with the conventions of roots.hpp (tangent flags,
// identically_zero, exact-zero leading coefficients lower the degree).
Roots solve(Polynomial polynomial);

}  // namespace cwe::detail
