#pragma once
// Helpers shared by the process tests.

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

}  // namespace cwe::test
