// Tri-dexel material removal: moves per second for 1 mm pocketing segments of a 10 mm flat end
// mill, 3 mm deep, in a 100 × 100 × 40 mm block (the pocketing job of the tri-dexel issue, first
// level only), at the ray spacing given as the benchmark argument (in µm).
#include <benchmark/benchmark.h>

#include "cwe/envelope/linear_sweep.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"

namespace {

void BM_PocketSegments(benchmark::State& state) {
  const double spacing = static_cast<double>(state.range(0)) * 1e-3;
  const cwe::Cutter cutter = cwe::cutter_from_spec("flat:10,30");
  cwe::TriDexel stock = cwe::TriDexel::from_box(cwe::Aabb{{0, 0, 0}, {100, 100, 40}}, spacing);
  double x = 10.0, y = 10.0;
  int direction = 1;
  for (auto _ : state) {
    // Zig-zag: 1 mm steps along X, 8 mm stepover at the ends.
    cwe::Vec3 from(x, y, 37.0), to(x + direction, y, 37.0);
    if (to.x() > 90.0 || to.x() < 10.0) {
      direction = -direction;
      to = cwe::Vec3(x, y + 8.0, 37.0);
    }
    const cwe::LinearSweep sweep(cutter, from, to, cwe::Vec3::UnitZ());
    benchmark::DoNotOptimize(
        stock.remove(sweep.bounds(), [&sweep](const cwe::Ray& ray) { return sweep.chord(ray); }));
    x = to.x();
    y = to.y() > 90.0 ? 10.0 : to.y();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["bytes_per_ray"] =
      static_cast<double>(stock.memory().total()) / static_cast<double>(stock.ray_count());
}
BENCHMARK(BM_PocketSegments)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace
