// Tests of the real-root solvers (roots.hpp): polynomials built from known roots, random
// polynomials against a dense sign-change oracle, degenerate inputs, and the scalar solvers.
#include "cwe/geometry/roots.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cwe/geometry/vec.hpp"
#include "random.hpp"

namespace cwe {
namespace {

// Unit roundoff of double, for tolerances derived from rounding-error bounds.
constexpr double kU = std::numeric_limits<double>::epsilon() / 2;

// 113-bit floating point, used to check that test polynomials are exactly representable.
__extension__ using Quad = __float128;

// Coefficients (highest degree first) of leading · Π (t - root).
template <typename Real>
std::vector<Real> expand(double leading, const std::vector<double>& roots) {
  std::vector<Real> coefficients{static_cast<Real>(leading)};
  for (const double root : roots) {
    coefficients.push_back(0);
    for (std::size_t i = coefficients.size() - 1; i > 0; --i) {
      coefficients[i] -= static_cast<Real>(root) * coefficients[i - 1];
    }
  }
  return coefficients;
}

std::vector<double> to_double(const std::vector<Quad>& coefficients) {
  std::vector<double> out;
  out.reserve(coefficients.size());
  for (const Quad c : coefficients) out.push_back(static_cast<double>(c));
  return out;
}

Roots solve(const std::vector<double>& c) {
  switch (c.size()) {
    case 3:
      return solve_quadratic(c[0], c[1], c[2]);
    case 4:
      return solve_cubic(c[0], c[1], c[2], c[3]);
    default:
      return solve_quartic(c[0], c[1], c[2], c[3], c[4]);
  }
}

double evaluate(const std::vector<double>& c, double t) {
  double value = 0.0;
  for (const double coefficient : c) value = value * t + coefficient;
  return value;
}

// Σ |c_i| |t|^(n-i): the size of the terms whose rounding decides p(t).
double magnitude(const std::vector<double>& c, double t) {
  double value = 0.0;
  for (const double coefficient : c) value = value * std::abs(t) + std::abs(coefficient);
  return value;
}

std::string describe(const std::vector<double>& c) {
  std::ostringstream out;
  out.precision(17);
  out << " of the polynomial with coefficients";
  for (const double coefficient : c) out << ' ' << coefficient;
  return out.str();
}

// Coefficients of p'.
std::vector<double> differentiate(const std::vector<double>& c) {
  std::vector<double> out;
  const std::size_t degree = c.size() - 1;
  for (std::size_t i = 0; i < degree; ++i) out.push_back(c[i] * static_cast<double>(degree - i));
  return out;
}

std::vector<double> found_roots(const Roots& roots) { return {roots.begin(), roots.end()}; }

bool is_sorted_strictly(const Roots& roots) {
  for (int i = 0; i + 1 < roots.size(); ++i) {
    if (!(roots[i] < roots[i + 1])) return false;
  }
  return true;
}

// --- Exact polynomials: dyadic roots make every coefficient exactly representable, so double
// roots are exactly double and the solver must report them once, flagged tangent.

struct KnownRoot {
  double value;
  int multiplicity;
};

// Draws a dyadic root: an integer multiple of 2^-k with few significant bits.
double dyadic(test::Random& rng, int bits, int exponent) {
  return std::ldexp(static_cast<double>(rng.integer(-(1 << bits), 1 << bits)), exponent);
}

void expect_exact_roots(const std::vector<KnownRoot>& known, double leading) {
  std::vector<double> all;
  for (const KnownRoot& k : known) {
    for (int m = 0; m < k.multiplicity; ++m) all.push_back(k.value);
  }
  const std::vector<Quad> exact = expand<Quad>(leading, all);
  const std::vector<double> c = to_double(exact);
  for (std::size_t i = 0; i < c.size(); ++i) {
    ASSERT_TRUE(static_cast<Quad>(c[i]) == exact[i]) << "test polynomial is not exact";
  }
  const Roots roots = solve(c);
  ASSERT_EQ(roots.size(), static_cast<int>(known.size()));
  EXPECT_FALSE(roots.identically_zero);
  EXPECT_TRUE(is_sorted_strictly(roots));
  std::vector<KnownRoot> sorted = known;
  std::sort(sorted.begin(), sorted.end(),
            [](const KnownRoot& a, const KnownRoot& b) { return a.value < b.value; });
  for (int i = 0; i < roots.size(); ++i) {
    const KnownRoot& k = sorted[static_cast<std::size_t>(i)];
    // Even with exact coefficients no solver in doubles does better than the root's condition:
    // a root of multiplicity m is a simple root of p^(m-1), which evaluates with a rounding of
    // a few u·Σ|c_i^(m-1)||r|^i, so the root moves by that over |p^(m)(r)|. The solver's Horner
    // bound is γ_2n ≈ 2n·u of the same sum: 64u covers it with margin, plus 8 ulps of r.
    std::vector<double> derivative = c;
    for (int order = 1; order < k.multiplicity; ++order) derivative = differentiate(derivative);
    double slope = leading;  // p^(m)(r) = m!·leading·Π_(other roots)(r - r_j)
    for (int order = 2; order <= k.multiplicity; ++order) slope *= order;
    for (const KnownRoot& other : known) {
      if (other.value == k.value) continue;
      for (int m = 0; m < other.multiplicity; ++m) slope *= k.value - other.value;
    }
    const double tolerance =
        64 * kU * magnitude(derivative, k.value) / std::abs(slope) + 8 * kU * std::abs(k.value);
    EXPECT_NEAR(roots[i], k.value, tolerance) << "root " << i << describe(c);
    EXPECT_EQ(roots.tangent[static_cast<std::size_t>(i)], k.multiplicity % 2 == 0)
        << "root " << k.value << " multiplicity " << k.multiplicity << describe(c);
  }
}

TEST(Roots, ExactPolynomialsWithDoubleRoots) {
  test::Random rng(1);
  for (int trial = 0; trial < 300; ++trial) {
    const double leading = dyadic(rng, 3, -1);
    if (leading == 0.0) continue;
    // Quadratic: double root, or two distinct roots.
    const double r1 = dyadic(rng, 6, -2);
    double r2 = dyadic(rng, 6, -2);
    expect_exact_roots({{r1, 2}}, leading);
    if (r2 != r1) expect_exact_roots({{r1, 1}, {r2, 1}}, leading);
    // Cubic: a double root and a simple one.
    while (r2 == r1) r2 = dyadic(rng, 6, -2);
    expect_exact_roots({{r1, 2}, {r2, 1}}, leading);
    // Quartic: two double roots; a double root and two simple ones.
    expect_exact_roots({{r1, 2}, {r2, 2}}, leading);
    double r3 = dyadic(rng, 6, -2);
    while (r3 == r1 || r3 == r2) r3 = dyadic(rng, 6, -2);
    expect_exact_roots({{r1, 2}, {r2, 1}, {r3, 1}}, leading);
  }
}

TEST(Roots, ExactHigherMultiplicities) {
  expect_exact_roots({{1.0, 3}}, 1.0);             // (t-1)³: odd, crosses zero
  expect_exact_roots({{1.0, 4}}, 1.0);             // (t-1)⁴: touches
  expect_exact_roots({{-0.5, 3}, {2.0, 1}}, 2.0);  // triple and simple
  expect_exact_roots({{0.0, 2}, {3.0, 2}}, -1.0);  // double root at zero
}

TEST(Roots, ExactRootsOfVeryDifferentMagnitude) {
  // 2^-20 ≈ 1e-6 next to roots near 1e3: a coefficient-size scan would miss the small root.
  const double small = std::ldexp(1.0, -20);
  expect_exact_roots({{small, 1}, {1000.0, 1}}, 1.0);
  expect_exact_roots({{small, 1}, {1000.0, 1}, {-3.0, 1}}, 1.0);
  expect_exact_roots({{small, 1}, {1000.0, 1}, {-3.0, 1}, {1024.0, 1}}, 1.0);
  expect_exact_roots({{-small, 1}, {small, 1}, {1000.0, 1}, {-3.0, 1}}, 0.5);
  // With double roots the t² coefficient holds both small² and 1000²: exact only for a ratio
  // up to about 2^26 (the roots of a rounded polynomial are the next test's business).
  const double less_small = std::ldexp(1.0, -10);
  expect_exact_roots({{less_small, 2}, {1000.0, 2}}, 1.0);
  expect_exact_roots({{less_small, 2}, {1000.0, 1}, {-3.0, 1}}, 1.0);
}

// --- Random real roots: the coefficients are rounded, so each root moves by its condition
// number times the coefficient rounding; the tolerance is that first-order bound.

// First-order error of simple root r of leading·Π(t - r_j) under relative coefficient
// perturbations of size `relative`: Σ|c_i||r|^i · relative / |p'(r)|.
double simple_root_tolerance(const std::vector<double>& c, const std::vector<double>& roots,
                             std::size_t index, double leading, double relative) {
  double derivative = leading;
  for (std::size_t j = 0; j < roots.size(); ++j) {
    if (j != index) derivative *= roots[index] - roots[j];
  }
  return relative * magnitude(c, roots[index]) / std::abs(derivative);
}

void expect_simple_roots(const std::vector<double>& known, double leading) {
  const std::vector<double> c = to_double(expand<Quad>(leading, known));
  const Roots roots = solve(c);
  std::vector<double> sorted = known;
  std::sort(sorted.begin(), sorted.end());
  ASSERT_EQ(roots.size(), static_cast<int>(sorted.size()));
  EXPECT_TRUE(is_sorted_strictly(roots));
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    // Coefficient rounding is u/2 (computed in 113 bits, rounded once); the solver adds a few
    // ulps of backward error (Horner's γ_2n): 64u covers both with margin. The result is also
    // never asked to be better than a few ulps of the root itself.
    const double tolerance =
        simple_root_tolerance(c, sorted, i, leading, 64 * kU) + 8 * kU * std::abs(sorted[i]);
    EXPECT_NEAR(roots[static_cast<int>(i)], sorted[i], tolerance)
        << "root " << i << " of " << sorted.size();
    EXPECT_FALSE(roots.tangent[i]);
  }
}

TEST(Roots, RandomSimpleRoots) {
  test::Random rng(2);
  for (int trial = 0; trial < 2000; ++trial) {
    const int degree = rng.integer(2, 4);
    std::vector<double> roots;
    roots.reserve(static_cast<std::size_t>(degree));
    for (int i = 0; i < degree; ++i) roots.push_back(rng.uniform(-10.0, 10.0));
    // Keep them apart by at least 1e-3 (closer roots are the clustered test's business).
    std::sort(roots.begin(), roots.end());
    bool separated = true;
    for (std::size_t i = 0; i + 1 < roots.size(); ++i) {
      separated = separated && roots[i + 1] - roots[i] > 1e-3;
    }
    if (!separated) continue;
    const double leading = rng.uniform(0.5, 2.0) * (rng.integer(0, 1) ? 1.0 : -1.0);
    expect_simple_roots(roots, leading);
  }
}

TEST(Roots, RandomRootsOfVeryDifferentMagnitude) {
  test::Random rng(3);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<double> roots{rng.uniform(0.5, 2.0) * 1e-6, rng.uniform(0.5, 2.0) * 1e3,
                              -rng.uniform(0.5, 2.0) * 1e3, rng.uniform(-10.0, -1.0)};
    const int degree = rng.integer(2, 4);
    roots.resize(static_cast<std::size_t>(degree));
    expect_simple_roots(roots, rng.uniform(0.5, 2.0));
  }
}

TEST(Roots, RandomClusteredRoots) {
  test::Random rng(4);
  for (int trial = 0; trial < 500; ++trial) {
    // n roots a relative δ apart: the critical values between them are ~δⁿ·|centre|ⁿ while the
    // coefficient rounding perturbs p by ~64u·(2|centre|)ⁿ. They stay real and first-order
    // perturbation theory (the tolerance below) holds while δⁿ ≫ 64u·2ⁿ: δ of 1e-5 (n = 2),
    // 1e-3 (n = 3) and 1e-2 (n = 4) leave a factor ≥ 1e4. Closer clusters are not resolvable
    // from rounded coefficients by any method.
    const double centre = rng.uniform(-5.0, 5.0);
    const int degree = rng.integer(2, 4);
    const double relative = degree == 2 ? 1e-5 : (degree == 3 ? 1e-3 : 1e-2);
    const double spread = std::max(std::abs(centre), 1.0) * relative * rng.uniform(1.0, 3.0);
    std::vector<double> roots;
    roots.reserve(static_cast<std::size_t>(degree));
    for (int i = 0; i < degree; ++i) roots.push_back(centre + i * spread);
    expect_simple_roots(roots, rng.uniform(0.5, 2.0));
  }
}

// --- Random coefficients: residual bound and a dense sign-change oracle.

TEST(Roots, RandomCoefficientsResidualAndSignChanges) {
  test::Random rng(5);
  constexpr int kSamples = 5000;  // grid spacing 2·bound / 5000 ≤ 0.009 (bound ≤ 21)
  for (int trial = 0; trial < 600; ++trial) {
    const int degree = rng.integer(2, 4);
    std::vector<double> c;
    for (int i = 0; i <= degree; ++i) c.push_back(rng.uniform(-1.0, 1.0));
    if (std::abs(c[0]) < 0.05) c[0] = 0.05;  // keep the Cauchy bound (scan range) modest
    const Roots roots = solve(c);
    ASSERT_TRUE(is_sorted_strictly(roots));
    double bound = 0.0;
    for (std::size_t i = 1; i < c.size(); ++i) bound = std::max(bound, std::abs(c[i] / c[0]));
    bound += 1.0;  // Cauchy: every root has |t| < 1 + max|c_i/c_0|
    for (const double t : roots) {
      EXPECT_LT(std::abs(t), bound);
      // A root a few ulps from the exact one leaves a residual of |p'(t)|·|t|·few·u ≤
      // n·Σ|c_i||t|^i·few·u, plus the evaluation's γ_2n Σ|c_i||t|^i. 32n·u is that with margin.
      EXPECT_LE(std::abs(evaluate(c, t)), 32.0 * degree * kU * magnitude(c, t))
          << "degree " << degree << " root " << t;
    }
    // Oracle: every cell of a dense grid over the Cauchy interval whose end values have
    // opposite signs (each beyond its evaluation error γ_2n Σ|c_i||t|^i) contains a root.
    const double step = 2.0 * bound / kSamples;
    double previous_t = -bound;
    double previous = evaluate(c, previous_t);
    for (int k = 1; k <= kSamples; ++k) {
      const double t = -bound + k * step;
      const double value = evaluate(c, t);
      const double noise = 4.0 * degree * kU * magnitude(c, t);
      const double previous_noise = 4.0 * degree * kU * magnitude(c, previous_t);
      if (std::abs(value) > noise && std::abs(previous) > previous_noise &&
          (value > 0.0) != (previous > 0.0)) {
        bool found = false;
        for (const double root : roots) found = found || (root >= previous_t && root <= t);
        EXPECT_TRUE(found) << "degree " << degree << ": sign change in [" << previous_t << ", " << t
                           << "] without a root";
      }
      previous_t = t;
      previous = value;
    }
  }
}

// --- Closed-form and degenerate cases.

TEST(Roots, QuadraticWithoutCancellation) {
  // t² - 1e8 t + 1: roots 1e-8 and 1e8. The textbook formula loses the small root entirely
  // ((1e8 - √(1e16 - 4)) / 2 cancels); q = -(b + sign(b)√Δ)/2 keeps it to a few ulps.
  const Roots roots = solve_quadratic(1.0, -1e8, 1.0);
  ASSERT_EQ(roots.size(), 2);
  EXPECT_NEAR(roots[0], 1e-8, 4 * kU * 1e-8);
  EXPECT_NEAR(roots[1], 1e8, 4 * kU * 1e8);
}

TEST(Roots, QuadraticCases) {
  Roots roots = solve_quadratic(1.0, -2.0, 1.0);  // (t-1)²
  ASSERT_EQ(roots.size(), 1);
  EXPECT_EQ(roots[0], 1.0);
  EXPECT_TRUE(roots.tangent[0]);
  EXPECT_TRUE(solve_quadratic(1.0, 0.0, 1.0).empty());  // t² + 1
  roots = solve_quadratic(2.0, 0.0, -8.0);              // ±2, b = 0
  ASSERT_EQ(roots.size(), 2);
  EXPECT_EQ(roots[0], -2.0);
  EXPECT_EQ(roots[1], 2.0);
  roots = solve_quadratic(1.0, 0.0, 0.0);  // t² = 0
  ASSERT_EQ(roots.size(), 1);
  EXPECT_EQ(roots[0], 0.0);
  EXPECT_TRUE(roots.tangent[0]);
  // Huge and tiny coefficients: scaling by a power of two keeps b² finite.
  roots = solve_quadratic(1e200, -3e200, 2e200);
  ASSERT_EQ(roots.size(), 2);
  EXPECT_NEAR(roots[0], 1.0, 4 * kU);
  EXPECT_NEAR(roots[1], 2.0, 8 * kU);
  roots = solve_quadratic(1e-200, -3e-200, 2e-200);
  ASSERT_EQ(roots.size(), 2);
  EXPECT_NEAR(roots[0], 1.0, 4 * kU);
  EXPECT_NEAR(roots[1], 2.0, 8 * kU);
  // A discriminant that is positive only by rounding: (t - 0.1)² expanded in doubles.
  roots = solve_quadratic(1.0, -0.2, 0.1 * 0.1);
  ASSERT_EQ(roots.size(), 1);
  EXPECT_TRUE(roots.tangent[0]);
  EXPECT_NEAR(roots[0], 0.1, 4 * kU);
}

TEST(Roots, DegenerateLeadingCoefficients) {
  // Exactly zero leading coefficients lower the degree.
  Roots roots = solve_quartic(0.0, 0.0, 1.0, -3.0, 2.0);  // t² - 3t + 2
  ASSERT_EQ(roots.size(), 2);
  EXPECT_EQ(roots[0], 1.0);
  EXPECT_EQ(roots[1], 2.0);
  roots = solve_quartic(0.0, 1.0, -6.0, 11.0, -6.0);  // (t-1)(t-2)(t-3)
  ASSERT_EQ(roots.size(), 3);
  EXPECT_NEAR(roots[0], 1.0, 8 * kU);
  EXPECT_NEAR(roots[1], 2.0, 16 * kU);
  EXPECT_NEAR(roots[2], 3.0, 16 * kU);
  roots = solve_cubic(0.0, 0.0, 2.0, -1.0);  // linear
  ASSERT_EQ(roots.size(), 1);
  EXPECT_EQ(roots[0], 0.5);
  EXPECT_FALSE(roots.tangent[0]);
  roots = solve_quadratic(0.0, 4.0, 1.0);
  ASSERT_EQ(roots.size(), 1);
  EXPECT_EQ(roots[0], -0.25);
  // A non-zero constant: no root, not identically zero.
  for (const Roots& r : {solve_quadratic(0.0, 0.0, 3.0), solve_cubic(0.0, 0.0, 0.0, -1.0),
                         solve_quartic(0.0, 0.0, 0.0, 0.0, 2.0)}) {
    EXPECT_TRUE(r.empty());
    EXPECT_FALSE(r.identically_zero);
  }
  // A tiny but non-zero leading coefficient keeps the degree: t·(1e-30 t + 1) has a root near
  // -1e30, beyond the largest parameter a caller could use but found within kRootSearchLimit.
  roots = solve_quadratic(1e-30, 1.0, 0.0);
  ASSERT_EQ(roots.size(), 2);
  EXPECT_NEAR(roots[0], -1e30, 1e30 * 8 * kU);
  EXPECT_EQ(roots[1], 0.0);
  // ... unless it lies beyond kRootSearchLimit (here past the range of doubles, -1e320).
  roots = solve_quadratic(1e-320, 1.0, -1.0);
  ASSERT_EQ(roots.size(), 1);
  EXPECT_EQ(roots[0], 1.0);
  EXPECT_FALSE(roots.tangent[0]);
  roots = solve_cubic(1e-320, 0.0, 1.0, -1.0);  // other roots ≈ ±1e160 i
  ASSERT_EQ(roots.size(), 1);
  EXPECT_NEAR(roots[0], 1.0, 4 * kU);
  roots = solve_quartic(1e-320, 0.0, 0.0, 1.0, -1.0);
  ASSERT_EQ(roots.size(), 1);
  EXPECT_NEAR(roots[0], 1.0, 4 * kU);
}

TEST(Roots, ZeroPolynomial) {
  for (const Roots& r : {solve_quadratic(0.0, 0.0, 0.0), solve_cubic(0.0, 0.0, 0.0, 0.0),
                         solve_quartic(0.0, 0.0, 0.0, 0.0, 0.0)}) {
    EXPECT_TRUE(r.empty());
    EXPECT_TRUE(r.identically_zero);
  }
}

TEST(Roots, PushKeepsOrder) {
  Roots roots;
  roots.push(3.0);
  roots.push(-1.0, true);
  roots.push(2.0);
  roots.push(-5.0);
  ASSERT_EQ(roots.size(), 4);
  EXPECT_EQ(found_roots(roots), (std::vector<double>{-5.0, -1.0, 2.0, 3.0}));
  EXPECT_TRUE(roots.tangent[1]);
  EXPECT_FALSE(roots.tangent[0] || roots.tangent[2] || roots.tangent[3]);
}

// --- a sin φ + b cos φ + c = 0.

double sin_cos(double a, double b, double c, double phi) {
  return a * std::sin(phi) + b * std::cos(phi) + c;
}

TEST(SinCos, RandomAgainstScan) {
  test::Random rng(6);
  constexpr int kSamples = 20000;
  for (int trial = 0; trial < 500; ++trial) {
    const double a = rng.uniform(-3.0, 3.0);
    const double b = rng.uniform(-3.0, 3.0);
    const double c = rng.uniform(-4.0, 4.0);
    const Roots roots = solve_sin_cos(a, b, c);
    ASSERT_TRUE(is_sorted_strictly(roots));
    const double size = std::abs(a) + std::abs(b) + std::abs(c);
    for (const double phi : roots) {
      EXPECT_GE(phi, 0.0);
      EXPECT_LT(phi, kTwoPi);
      // Newton-polished: the residual is the rounding of sin, cos and the sum, a few u·size.
      EXPECT_LE(std::abs(sin_cos(a, b, c, phi)), 8 * kU * size);
    }
    if (std::hypot(a, b) < std::abs(c)) {
      EXPECT_TRUE(roots.empty());
    }
    // Oracle: each sign change on a dense grid of [0, 2π] holds a root. The wrap from 2π back
    // to 0 is the same angle, so the last cell is [φ_last, 2π).
    double previous_phi = 0.0;
    double previous = sin_cos(a, b, c, 0.0);
    for (int k = 1; k <= kSamples; ++k) {
      const double phi = kTwoPi * k / kSamples;
      const double value = sin_cos(a, b, c, phi);
      const double noise = 8 * kU * size;
      if (std::abs(value) > noise && std::abs(previous) > noise &&
          (value > 0.0) != (previous > 0.0)) {
        bool found = false;
        for (const double root : roots) {
          found = found || (root >= previous_phi && root <= phi) || (k == kSamples && root == 0.0);
        }
        EXPECT_TRUE(found) << "sign change in [" << previous_phi << ", " << phi << "]";
      }
      previous_phi = phi;
      previous = value;
    }
  }
}

TEST(SinCos, BranchesAreTheRootsAndContinuePastThem) {
  test::Random rng(16);
  for (int trial = 0; trial < 500; ++trial) {
    const double a = rng.uniform(-3.0, 3.0), b = rng.uniform(-3.0, 3.0), c = rng.uniform(-4.0, 4.0);
    const double rho = std::hypot(a, b), delta = std::atan2(b, a);
    const double size = std::abs(a) + std::abs(b) + std::abs(c);
    for (int branch = 0; branch < 2; ++branch) {
      bool exists = false;
      const double phi = sin_cos_branch(rho, delta, c, branch, exists);
      ASSERT_EQ(exists, std::abs(c) <= rho) << a << " " << b << " " << c;
      if (exists) {
        // Unpolished: asin's rounding near ±1 is amplified by 1/√(1 - s²); away from the
        // tangent case a few hundred u·size covers it.
        if (std::abs(c) < 0.99 * rho) {
          EXPECT_LE(std::abs(sin_cos(a, b, c, phi)), 256 * kU * size);
        }
      } else {
        // Continued with the sine clamped: the extremum of a sin φ + b cos φ nearest to -c.
        EXPECT_NEAR(a * std::sin(phi) + b * std::cos(phi), c > 0.0 ? -rho : rho, 1e-12 * size);
      }
    }
  }
}

TEST(SinCos, TangentNoRootAndConstant) {
  // 3 sin φ + 4 cos φ = 5 sin(φ + δ): touches -5 and +5 once each.
  for (const double c : {5.0, -5.0}) {
    const Roots roots = solve_sin_cos(3.0, 4.0, c);
    ASSERT_EQ(roots.size(), 1) << "c = " << c;
    EXPECT_TRUE(roots.tangent[0]);
    EXPECT_LE(std::abs(sin_cos(3.0, 4.0, c, roots[0])), 16 * kU * 12.0);
    // A minimum (or maximum) of the left side: the derivative vanishes there.
    EXPECT_LE(std::abs(3.0 * std::cos(roots[0]) - 4.0 * std::sin(roots[0])), 1e-12);
  }
  EXPECT_TRUE(solve_sin_cos(3.0, 4.0, 5.0 + 1e-9).empty());  // beyond reach
  EXPECT_EQ(solve_sin_cos(3.0, 4.0, 5.0 - 1e-9).size(), 2);  // two close roots
  // cos φ = 1: the tangent root is φ = 0, not 2π.
  Roots roots = solve_sin_cos(0.0, 1.0, -1.0);
  ASSERT_EQ(roots.size(), 1);
  EXPECT_GE(roots[0], 0.0);
  EXPECT_LT(roots[0], 1e-15);
  // a = b = 0.
  roots = solve_sin_cos(0.0, 0.0, 0.0);
  EXPECT_TRUE(roots.empty());
  EXPECT_TRUE(roots.identically_zero);
  roots = solve_sin_cos(0.0, 0.0, 1.0);
  EXPECT_TRUE(roots.empty());
  EXPECT_FALSE(roots.identically_zero);
  // sin φ = 0.5: π/6 and 5π/6.
  roots = solve_sin_cos(1.0, 0.0, -0.5);
  ASSERT_EQ(roots.size(), 2);
  EXPECT_NEAR(roots[0], kPi / 6, 4 * kU * kPi);
  EXPECT_NEAR(roots[1], 5 * kPi / 6, 4 * kU * kPi);
}

// --- Brent root and minimum.

TEST(Brent, RootOfKnownFunctions) {
  // cos x = x: the Dottie number.
  std::optional<double> root = brent_root([](double x) { return std::cos(x) - x; }, 0.0, 1.0);
  ASSERT_TRUE(root.has_value());
  // Default convergence: 4e-16|x| + 1e-15.
  EXPECT_NEAR(*root, 0.739085133215160641655, 4e-16 + 1e-15);
  root = brent_root([](double x) { return x * x * x - 2.0; }, 0.0, 2.0);
  ASSERT_TRUE(root.has_value());
  EXPECT_NEAR(*root, std::cbrt(2.0), 2 * 4e-16 + 1e-15);
  // A caller's looser tolerance is honoured (and the root still bracketed within it).
  root = brent_root([](double x) { return std::exp(x) - 3.0; }, 0.0, 5.0, 1e-6);
  ASSERT_TRUE(root.has_value());
  EXPECT_NEAR(*root, std::log(3.0), 1e-6);
  // Not a bracket; a zero end point is returned as is.
  EXPECT_FALSE(brent_root([](double x) { return x * x + 1.0; }, -1.0, 1.0).has_value());
  EXPECT_EQ(brent_root([](double x) { return x - 1.0; }, 1.0, 3.0), 1.0);
  EXPECT_EQ(brent_root([](double x) { return x - 3.0; }, 1.0, 3.0), 3.0);
  // A step function: Brent must still shrink the bracket onto the jump.
  root = brent_root([](double x) { return x < 0.3 ? -1.0 : 1.0; }, 0.0, 1.0);
  ASSERT_TRUE(root.has_value());
  EXPECT_NEAR(*root, 0.3, 1e-14);
}

TEST(Brent, MinimumOfKnownFunctions) {
  // Away from the minimum's flatness, x is found to √(rounding of f) relative: 1e-7 is above
  // √u ≈ 1.5e-8 times the scale with margin.
  Extremum m = brent_minimize([](double x) { return (x - 2.0) * (x - 2.0) + 1.0; }, 0.0, 5.0);
  EXPECT_NEAR(m.x, 2.0, 1e-7);
  EXPECT_NEAR(m.value, 1.0, 4 * kU);
  m = brent_minimize([](double x) { return std::cos(x); }, 0.0, kTwoPi);
  EXPECT_NEAR(m.x, kPi, 1e-7);
  EXPECT_NEAR(m.value, -1.0, 4 * kU);
  // Monotone: the smaller end.
  m = brent_minimize([](double x) { return std::exp(x); }, 0.0, 1.0);
  EXPECT_EQ(m.x, 0.0);
  EXPECT_EQ(m.value, 1.0);
  m = brent_minimize([](double x) { return -x; }, -1.0, 4.0);
  EXPECT_EQ(m.x, 4.0);
  // Minimum at an end of a non-monotone f: x(x - 3) on [2, 5] rises from 2.
  m = brent_minimize([](double x) { return x * (x - 3.0); }, 2.0, 5.0);
  EXPECT_NEAR(m.x, 2.0, 1e-7);
}

TEST(BracketedRoots, Cases) {
  const auto parabola = [](double x) { return x * x - 1.0; };
  // Two roots: equal signs at the ends, the minimum below zero (Rolle).
  Roots roots = bracketed_roots(parabola, -2.0, 2.0);
  ASSERT_EQ(roots.size(), 2);
  EXPECT_NEAR(roots[0], -1.0, 1e-15);
  EXPECT_NEAR(roots[1], 1.0, 1e-15);
  EXPECT_FALSE(roots.tangent[0] || roots.tangent[1]);
  // One root: opposite signs.
  roots = bracketed_roots(parabola, 0.0, 2.0);
  ASSERT_EQ(roots.size(), 1);
  EXPECT_NEAR(roots[0], 1.0, 1e-15);
  // None: the minimum stays positive.
  EXPECT_TRUE(bracketed_roots([](double x) { return x * x + 1.0; }, -2.0, 2.0).empty());
  // Maximum toward zero from below: -(x² - 1) has two roots too.
  roots = bracketed_roots([](double x) { return 1.0 - x * x; }, -3.0, 3.0);
  ASSERT_EQ(roots.size(), 2);
  // Tangent: (x - 0.5)² written as x² - x + 0.25 has a minimum of 0 up to rounding (≈ 1e-17);
  // the zero test uses the caller's tolerance, and the extremum's x is good to √(rounding).
  const auto touching = [](double x) { return x * x - x + 0.25; };
  roots = bracketed_roots(touching, 0.0, 2.0, 1e-15);
  ASSERT_EQ(roots.size(), 1);
  EXPECT_TRUE(roots.tangent[0]);
  EXPECT_NEAR(roots[0], 0.5, 1e-7);
  // Without a tolerance the same function only counts as tangent if it hits zero exactly.
  const Roots strict = bracketed_roots([](double x) { return x * x + 1e-3; }, -1.0, 1.0, 0.0);
  EXPECT_TRUE(strict.empty());
  // A zero end point and an interior crossing: x(x - 0.5) on [0, 1].
  roots = bracketed_roots([](double x) { return x * (x - 0.5); }, 0.0, 1.0);
  ASSERT_EQ(roots.size(), 2);
  EXPECT_EQ(roots[0], 0.0);
  EXPECT_NEAR(roots[1], 0.5, 1e-15);
}

}  // namespace
}  // namespace cwe
