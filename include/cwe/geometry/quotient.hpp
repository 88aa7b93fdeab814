#pragma once
// Tests and clamps of a quotient x / y (y > 0) that divide only where the quotient's rounding
// can change the answer: a division costs as much as a dozen other operations, and the removal
// kernels ask these of most rays. Each gives what the plain division gives, to the last bit
// (clamped_quotient: but for the sign of a zero); tests/geometry/quotient_test.cpp holds them
// to it, subnormal and tied quotients included.
//
// Why it is exact: rounding to nearest is monotone, so 0 ≤ x ≤ y gives 0 ≤ fl(x/y) ≤ fl(y/y) = 1,
// and x ≥ y gives fl(x/y) ≥ 1. Beyond those:
//  - x > y: x is at least y's successor, y + y/m for y's integer significand m < 2⁵³, so
//    x/y > 1 + 2⁻⁵³, the midpoint between 1 and the next double: fl(x/y) > 1.
//  - x < 0: fl(x/y) < 0 unless the quotient rounds to -0 (|x/y| ≤ 2⁻¹⁰⁷⁵), which lies in
//    [0, 1]. x < -fl(y·2⁻¹⁰⁰⁰) rules that out: for y ≥ 2⁻²² the product is exact and
//    x/y < -2⁻¹⁰⁰⁰; for smaller y any negative x (|x| ≥ 2⁻¹⁰⁷⁴) gives |x/y| > 2⁻¹⁰⁵². Nearer
//    0 the quotient is divided.

namespace cwe {

// Whether fl(x / y) lies in [0, 1], for y > 0.
inline bool quotient_in_unit(double x, double y) {
  if (x >= 0.0) return x <= y;
  if (x < -y * 0x1p-1000) return false;
  return x / y >= 0.0;  // -0 (or NaN: false)
}

// x / y where y is ±1 (an axis-aligned path's or ray's direction) without the division: x or
// -x, which the division gives exactly (a zero's sign too).
inline double quotient_by_unit(double x, double y) {
  return y == 1.0 ? x : (y == -1.0 ? -x : x / y);
}

// std::clamp(x / y, 0.0, 1.0) for y > 0; a zero result is +0 (the division may give -0).
inline double clamped_quotient(double x, double y) {
  if (x <= 0.0) return 0.0;
  if (x >= y) return 1.0;
  return x / y;  // in [0, 1] (see above)
}

}  // namespace cwe
