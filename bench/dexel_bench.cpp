// Tri-dexel material removal in a 100 × 100 × 40 mm block (the benchmark of the tri-dexel issue),
// at the ray spacing given as the benchmark argument (µm):
//  - PocketSegments: 1 mm zig-zag segments of a 10 mm flat end mill, 8 mm stepover, levels 3 mm
//    apart (3-axis level moves: the closed-form chords);
//  - BallRaster: a 6 mm ball end mill finishing a curved surface in 1 mm segments along X at
//    0.5 mm stepover (every segment climbs or descends: the general chord construction).
// Counters: moves per second, bytes per ray (current) and peak bytes per ray.
#include <benchmark/benchmark.h>

#include <cmath>

#include "cwe/envelope/linear_sweep.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"

namespace {

void report(benchmark::State& state, const cwe::TriDexel& stock) {
  state.SetItemsProcessed(state.iterations());
  const auto rays = static_cast<double>(stock.ray_count());
  state.counters["bytes_per_ray"] = static_cast<double>(stock.memory().total()) / rays;
  state.counters["peak_bytes_per_ray"] = static_cast<double>(stock.memory().peak()) / rays;
  state.counters["rays"] = rays;
}

void BM_PocketSegments(benchmark::State& state) {
  const double spacing = static_cast<double>(state.range(0)) * 1e-3;
  const cwe::Cutter cutter = cwe::cutter_from_spec("flat:10,30");
  cwe::TriDexel stock = cwe::TriDexel::from_box(cwe::Aabb{{0, 0, 0}, {100, 100, 40}}, spacing);
  double x = 10.0, y = 10.0, z = 37.0;
  int direction = 1;
  for (auto _ : state) {
    cwe::Vec3 from(x, y, z), to(x + direction, y, z);
    if (to.x() > 90.0 || to.x() < 10.0) {
      direction = -direction;
      to = cwe::Vec3(x, y + 8.0, z);
    }
    const cwe::LinearSweep sweep(cutter, from, to, cwe::Vec3::UnitZ());
    benchmark::DoNotOptimize(
        stock.remove(sweep.bounds(), [&sweep](const cwe::Ray& ray) { return sweep.chord(ray); }));
    x = to.x();
    y = to.y();
    if (y > 90.0) {  // next level
      y = 10.0;
      z = z > 10.0 ? z - 3.0 : 37.0;
    }
  }
  report(state, stock);
}
BENCHMARK(BM_PocketSegments)->Arg(100)->Arg(50)->Unit(benchmark::kMillisecond);

double surface(double x, double y) { return 32.0 + 4.0 * std::sin(x / 12.0) * std::cos(y / 17.0); }

void BM_BallRaster(benchmark::State& state) {
  const double spacing = static_cast<double>(state.range(0)) * 1e-3;
  const cwe::Cutter cutter = cwe::cutter_from_spec("ball:6,20");
  cwe::TriDexel stock = cwe::TriDexel::from_box(cwe::Aabb{{0, 0, 0}, {100, 100, 40}}, spacing);
  double x = 0.0, y = 0.0;
  int direction = 1;
  for (auto _ : state) {
    double nx = x + direction, ny = y;
    if (nx > 100.0 || nx < 0.0) {
      direction = -direction;
      nx = x;
      ny = y + 0.5 > 100.0 ? 0.0 : y + 0.5;
    }
    const cwe::Vec3 from(x, y, surface(x, y)), to(nx, ny, surface(nx, ny));
    const cwe::LinearSweep sweep(cutter, from, to, cwe::Vec3::UnitZ());
    benchmark::DoNotOptimize(
        stock.remove(sweep.bounds(), [&sweep](const cwe::Ray& ray) { return sweep.chord(ray); }));
    x = nx;
    y = ny;
  }
  report(state, stock);
}
BENCHMARK(BM_BallRaster)->Arg(100)->Arg(50)->Unit(benchmark::kMillisecond);

}  // namespace
