#include "cwe/io/fixed_decimal.hpp"

#include <cmath>
#include <cstdint>

namespace cwe {

char* write_fixed(char* out, double v, int decimals) {
  static constexpr double kScale[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  if (decimals < 0 || decimals > 9) return nullptr;
  const double m = kScale[decimals];
  const double hi = v * m;
  if (!(std::abs(hi) < 0x1p52)) return nullptr;  // also infinite and NaN values
  const double lo = std::fma(v, m, -hi);          // v·m = hi + lo exactly
  double n = std::nearbyint(hi);                  // ties to even (the default rounding)
  const double half = hi - n;                     // exact
  if (half == 0.5 && lo > 0.0) n += 1.0;
  if (half == -0.5 && lo < 0.0) n -= 1.0;
  if (std::signbit(v)) *out++ = '-';
  auto digits = static_cast<std::uint64_t>(std::abs(n));
  // The digits from the last: `decimals` after the point, then the whole part (at least "0").
  char buffer[kFixedDecimalMax];
  char* end = buffer + sizeof buffer;
  char* p = end;
  for (int k = 0; k < decimals; ++k) {
    *--p = static_cast<char>('0' + digits % 10);
    digits /= 10;
  }
  if (decimals > 0) *--p = '.';
  do {
    *--p = static_cast<char>('0' + digits % 10);
    digits /= 10;
  } while (digits != 0);
  while (p != end) *out++ = *p++;
  return out;
}

}  // namespace cwe
