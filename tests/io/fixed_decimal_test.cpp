// write_fixed against fmt's "{:.Nf}" (the text engagement.csv, engagement.jsonl and forces.csv
// held before), character for character: random values of every size the files hold, exact
// ties and their neighbours (where the binary value's last bits decide the rounding), signed
// zeros and tiny negatives, and the values it leaves to fmt.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "cwe/io/fixed_decimal.hpp"
#include "random.hpp"

namespace cwe {
namespace {

// The text of v at `decimals`, or "" where write_fixed leaves it to fmt.
std::string fixed(double v, int decimals) {
  char buffer[kFixedDecimalMax];
  const char* end = write_fixed(buffer, v, decimals);
  return end == nullptr ? std::string() : std::string(static_cast<const char*>(buffer), end);
}

// Where write_fixed takes v, its text is fmt's; it leaves v to fmt only beyond its range.
void expect_as_fmt(double v, int decimals) {
  const std::string ours = fixed(v, decimals);
  if (ours.empty()) {
    ASSERT_GE(std::abs(v * std::pow(10.0, decimals)), 0x1p52) << fmt::format("{:a}", v);
    return;
  }
  ASSERT_EQ(ours, fmt::format("{:.{}f}", v, decimals))
      << fmt::format("{:a} at {} decimals", v, decimals);
}

TEST(FixedDecimal, AsFmtOnRandomValues) {
  test::Random random(92);
  for (int k = 0; k < 300000; ++k) {
    const int decimals = random.integer(0, 9);
    const double v = std::ldexp(random.uniform(-1.0, 1.0), random.integer(-40, 30));
    expect_as_fmt(v, decimals);
  }
}

TEST(FixedDecimal, AsFmtAtTiesAndTheirNeighbours) {
  // Halfway values that are exact in binary (k/2^e with a 5 at decimal N + 1), and the doubles
  // on either side of them and of decimal halfway points that are not exact.
  test::Random random(93);
  int ties = 0;
  for (int k = 0; k < 200000; ++k) {
    const int decimals = random.integer(0, 6);
    const double unit = std::pow(10.0, -decimals);
    const double middle = (std::floor(random.uniform(-1e5, 1e5)) + 0.5) * unit;
    for (const double v : {middle, std::nextafter(middle, 0.0), std::nextafter(middle, 1e300),
                           std::nextafter(middle, -1e300)}) {
      expect_as_fmt(v, decimals);
    }
    const double exact = std::ldexp(std::floor(random.uniform(-4096.0, 4096.0)) + 0.5,
                                    -random.integer(0, 3));  // x.5, x.25, x.125, x.0625
    ties += fixed(exact, decimals).empty() ? 0 : 1;
    expect_as_fmt(exact, decimals);
  }
  EXPECT_EQ(ties, 200000);
  for (const double v : {0.25, 0.5, 1.5, 2.5, 0.0625, -2.5, 0.125, 1.125, -0.375}) {
    for (int decimals = 0; decimals <= 4; ++decimals) expect_as_fmt(v, decimals);
  }
}

TEST(FixedDecimal, SignsZerosAndTheValuesLeftToFmt) {
  for (int decimals = 0; decimals <= 9; ++decimals) {
    for (const double v : {0.0, -0.0, -1e-12, 1e-12, -0.4, 0.4, -4.9999999, 1e7, -123456.789,
                           std::numeric_limits<double>::denorm_min(),
                           -std::numeric_limits<double>::denorm_min()}) {
      expect_as_fmt(v, decimals);
    }
  }
  EXPECT_EQ(fixed(-0.0, 3), "-0.000");
  EXPECT_EQ(fixed(-0.0001, 3), "-0.000");
  EXPECT_EQ(fixed(2.5, 0), "2");
  EXPECT_EQ(fixed(0.0625, 3), "0.062");
  // Left to fmt: beyond 2^52 units of the last decimal, not finite, or an unknown precision.
  EXPECT_EQ(fixed(1e300, 3), "");
  EXPECT_EQ(fixed(0x1p52 / 1000.0, 3), "");
  EXPECT_EQ(fixed(std::nextafter(0x1p52 / 1000.0, 0.0), 3),
            fmt::format("{:.3f}", std::nextafter(0x1p52 / 1000.0, 0.0)));
  EXPECT_EQ(fixed(std::numeric_limits<double>::infinity(), 3), "");
  EXPECT_EQ(fixed(1.0, 10), "");
  EXPECT_EQ(fixed(1.0, -1), "");
}

}  // namespace
}  // namespace cwe
