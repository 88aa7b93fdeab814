// Throughput of the primitives every later stage leans on: polynomial roots, ray–torus chords
// (the corner of bull-nose cutters) and ray–cutter chords.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "cwe/geometry/intersect.hpp"
#include "cwe/geometry/roots.hpp"
#include "cwe/tool/tool_spec.hpp"

namespace {

std::vector<cwe::Ray> random_rays(int count, double half_size, unsigned seed) {
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> position(-half_size, half_size);
  std::normal_distribution<double> normal;
  std::vector<cwe::Ray> rays;
  for (int i = 0; i < count; ++i) {
    cwe::Vec3 d(normal(engine), normal(engine), normal(engine));
    rays.push_back(
        {cwe::Vec3(position(engine), position(engine), position(engine)), d.normalized()});
  }
  return rays;
}

void BM_SolveQuartic(benchmark::State& state) {
  std::mt19937_64 engine(1);
  std::uniform_real_distribution<double> root(-10.0, 10.0);
  std::vector<std::array<double, 5>> polys;
  for (int i = 0; i < 1024; ++i) {
    const double a = root(engine), b = root(engine), c = root(engine), d = root(engine);
    // (t-a)(t-b)(t-c)(t-d)
    polys.push_back({1.0, -(a + b + c + d), a * b + a * c + a * d + b * c + b * d + c * d,
                     -(a * b * c + a * b * d + a * c * d + b * c * d), a * b * c * d});
  }
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& p = polys[i++ & 1023];
    benchmark::DoNotOptimize(cwe::solve_quartic(p[0], p[1], p[2], p[3], p[4]));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SolveQuartic);

void BM_RayTorus(benchmark::State& state) {
  const auto rays = random_rays(1024, 6.0, 2);
  const cwe::Torus torus{cwe::Vec3::Zero(), cwe::Vec3::UnitZ(), 3.0, 2.0};
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(cwe::intersect(rays[i++ & 1023], torus));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RayTorus);

void BM_RayCutter(benchmark::State& state, const char* spec) {
  const cwe::Cutter cutter = cwe::cutter_from_spec(spec);
  auto rays = random_rays(1024, 8.0, 3);
  for (auto& r : rays) r.origin.z() += 8.0;
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(cutter.intersect(rays[i++ & 1023]));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(BM_RayCutter, flat, "flat:10,20");
BENCHMARK_CAPTURE(BM_RayCutter, ball, "ball:10,20");
BENCHMARK_CAPTURE(BM_RayCutter, bull, "bull:10,2,20");

}  // namespace
