#pragma once
// Helpers shared by the process tests.

#include <cmath>

#include "cwe/geometry/vec.hpp"
#include "cwe/process/cutting_coefficients.hpp"

namespace cwe::test {

// An Al7075-like set (N/mm², N/mm): the numbers only need to be realistic and all different.
inline CuttingCoefficients test_coefficients() {
  CuttingCoefficients k;
  k.ktc = 796.0;
  k.krc = 168.8;
  k.kac = 222.0;
  k.kte = 27.7;
  k.kre = 30.8;
  k.kae = 1.8;
  return k;
}

// Closed-form mean forces of a flat end mill between φ_st and φ_ex (docs/forces.md, derived
// by integrating the element forces over [φ_st, φ_ex] and dividing by 2π; z with this model's
// sign, dF_z = −dF_a on a cylinder).
inline Vec3 closed_form_mean(const CuttingCoefficients& k, int flutes, double a, double c, double st,
                      double ex) {
  auto fx = [&](double p) {
    return flutes * a * c / (8 * kPi) *
               (k.ktc * std::cos(2 * p) - k.krc * (2 * p - std::sin(2 * p))) +
           flutes * a / (2 * kPi) * (-k.kte * std::sin(p) + k.kre * std::cos(p));
  };
  auto fy = [&](double p) {
    return flutes * a * c / (8 * kPi) *
               (k.ktc * (2 * p - std::sin(2 * p)) + k.krc * std::cos(2 * p)) -
           flutes * a / (2 * kPi) * (k.kte * std::cos(p) + k.kre * std::sin(p));
  };
  auto fz = [&](double p) {
    return -flutes * a / (2 * kPi) * (-k.kac * c * std::cos(p) + k.kae * p);
  };
  return {fx(ex) - fx(st), fy(ex) - fy(st), fz(ex) - fz(st)};
}

}  // namespace cwe::test
