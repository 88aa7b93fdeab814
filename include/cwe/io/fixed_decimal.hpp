#pragma once
// Fixed-point decimal text of a double, exactly as printf's "%.*f" and fmt's "{:.Nf}" give it
// (the binary value rounded to N decimals, a tie to even; a minus sign on every negative value
// and on -0), about three times faster (20 to 30 ns a number against fmt's 60 to 90): the
// output files engagement.jsonl, engagement.csv and forces.csv format about a hundred numbers at
// each cutter location.
//
// How: with m = 10^N, the product v·m is exactly hi + lo (hi = fl(v·m), lo = fma(v, m, -hi)),
// and hi's nearest integer n0 (ties to even) is the answer unless hi lies halfway between two
// integers, where lo's sign decides. Away from halfway, |hi - n0| ≤ 1/2 - ulp(hi) and
// |lo| ≤ ulp(hi)/2 keep v·m nearer n0. Values with |v·m| ≥ 2⁵² (or not finite) are left to fmt.

#include <cstddef>

namespace cwe {

// The longest text write_fixed writes.
inline constexpr std::size_t kFixedDecimalMax = 32;

// Writes v with `decimals` (0 to 9) decimals at `out` (room for kFixedDecimalMax characters) and
// returns the end; nullptr, writing nothing, where v is out of its range (|v|·10^decimals ≥ 2⁵²,
// infinite or NaN) or `decimals` is.
char* write_fixed(char* out, double v, int decimals);

}  // namespace cwe
