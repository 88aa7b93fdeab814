// quotient_in_unit and clamped_quotient against the plain division, bit for bit: random
// quotients about 0 and 1, and the edges where rounding decides (subnormal and tied quotients,
// quotients within an ulp of 1, signed zeros, infinities).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "cwe/geometry/quotient.hpp"
#include "random.hpp"

namespace cwe {
namespace {

bool divided_in_unit(double x, double y) {
  const double q = x / y;
  return q >= 0.0 && q <= 1.0;
}

void expect_as_divided(double x, double y) {
  ASSERT_EQ(quotient_in_unit(x, y), divided_in_unit(x, y)) << x << " / " << y;
  const double clamped = std::clamp(x / y, 0.0, 1.0), fast = clamped_quotient(x, y);
  if (std::isnan(clamped)) {
    ASSERT_TRUE(std::isnan(fast)) << x << " / " << y;
  } else if (clamped == 0.0) {
    ASSERT_EQ(std::bit_cast<std::uint64_t>(fast), std::bit_cast<std::uint64_t>(0.0))
        << x << " / " << y;
  } else {
    ASSERT_EQ(std::bit_cast<std::uint64_t>(fast), std::bit_cast<std::uint64_t>(clamped))
        << x << " / " << y;
  }
}

TEST(Quotient, AsTheDivisionOnRandomQuotients) {
  test::Random random(91);
  for (int k = 0; k < 200000; ++k) {
    const double y = std::ldexp(random.uniform(1.0, 2.0), random.integer(-60, 60));
    const double q = k % 2 == 0 ? random.uniform(-0.5, 1.5) : 1.0 + random.uniform(-1e-15, 1e-15);
    expect_as_divided(q * y, y);
  }
}

TEST(Quotient, AsTheDivisionAtTheEdges) {
  const double tiny = std::numeric_limits<double>::denorm_min();
  const double min = std::numeric_limits<double>::min();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> ys{1.0, 2.0, 3.0, 0.5, 1e-300, min, tiny, 1e300, 4.0, 0x1p-22, 0x1p-23};
  int cases = 0;
  for (const double y : ys) {
    std::vector<double> xs{0.0,
                           -0.0,
                           tiny,
                           -tiny,
                           2 * tiny,
                           -2 * tiny,
                           3 * tiny,
                           -3 * tiny,
                           min,
                           -min,
                           y,
                           -y,
                           std::nextafter(y, inf),
                           std::nextafter(y, -inf),
                           y * (1.0 + 0x1p-50),
                           y * (1.0 + 0x1p-52),
                           -y * 0x1p-1000,
                           std::nextafter(-y * 0x1p-1000, -inf),
                           std::nextafter(-y * 0x1p-1000, inf),
                           std::ldexp(y, -1074),
                           std::ldexp(-y, -1075),
                           std::ldexp(-y, -1076),
                           inf,
                           -inf};
    for (const double x : xs) {
      expect_as_divided(x, y);
      ++cases;
    }
  }
  // A quotient tied between 0 and the smallest subnormal rounds to -0, inside [0, 1].
  expect_as_divided(-tiny, 2.0);
  EXPECT_TRUE(quotient_in_unit(-tiny, 2.0));
  EXPECT_EQ(cases, 24 * static_cast<int>(ys.size()));
}

// quotient_by_unit is the division, bit for bit (a zero's sign too), by ±1 and by others.
TEST(Quotient, ByUnitIsTheDivision) {
  const double inf = std::numeric_limits<double>::infinity();
  int cases = 0;
  for (const double y : {1.0, -1.0, 2.0, -0.5, 3.0, 1e-300}) {
    for (const double x : {0.0, -0.0, 1.0, -1.0, 0.1, -7.25, 1e308, -1e-320, inf, -inf}) {
      EXPECT_EQ(std::bit_cast<std::uint64_t>(quotient_by_unit(x, y)),
                std::bit_cast<std::uint64_t>(x / y))
          << x << " / " << y;
      ++cases;
    }
  }
  EXPECT_EQ(cases, 60);
}

}  // namespace
}  // namespace cwe
