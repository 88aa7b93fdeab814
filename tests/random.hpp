#pragma once
// Seeded random inputs for property and oracle tests: every run draws the same values, so a
// failure is reproducible from the test name alone.

#include <cstdint>
#include <random>

#include "cwe/geometry/vec.hpp"

namespace cwe::test {

class Random {
 public:
  explicit Random(std::uint64_t seed = 20081117) : engine_(seed) {}

  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(engine_);
  }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(engine_); }
  Vec3 point_in_box(double half_size) {
    return {uniform(-half_size, half_size), uniform(-half_size, half_size),
            uniform(-half_size, half_size)};
  }
  // Uniform on the unit sphere.
  Vec3 unit_vector() {
    std::normal_distribution<double> normal;
    Vec3 v;
    do {
      v = {normal(engine_), normal(engine_), normal(engine_)};
    } while (v.norm() < 1e-3);
    return v.normalized();
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace cwe::test
