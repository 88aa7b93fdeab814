// Tri-dexel material removal in a 100 × 100 × 40 mm block (the benchmark of the tri-dexel issue),
// at the ray spacing given as the benchmark argument (µm). One iteration runs a whole job on a
// fresh stock (making the stock is not timed); items are moves, timed in wall-clock time.
//  - PocketJob: 1 mm zig-zag segments of a 10 mm flat end mill, 8 mm stepover, five levels 3 mm
//    apart (4,450 moves; level moves use the closed-form chords), through remove_toolpath
//    (batched removal, as `cwe simulate` runs it);
//  - PocketOneByOne: the same moves, one TriDexel::remove per move (the path engagement takes,
//    which must see the workpiece between moves);
//  - BallRaster: a 6 mm ball end mill finishing a curved surface, 1 mm segments along X at
//    0.5 mm stepover, five passes (500 moves; every segment climbs or descends: the general
//    chord construction);
//  - BullRaster: the same with a 10 mm bull-nose end mill of corner radius 2 (the swept grazing
//    curves of the torus, followed by Brent's method per ray).
//  - StockBox: the block made at s = 0.1 (1,800,000 rays), as a job's set-up makes its stock;
//    items are rays.
//  - PocketMesh: the block after PocketJob at s = 0.1 contoured as `cwe simulate` contours
//    stock.stl (dexel_mesh at stride 3, about 930,000 triangles); items are triangles.
//  - PocketStl: that mesh's binary STL facets encoded (not written); items are triangles.
// Counters: moves per second, bytes per ray (current) and peak bytes per ray, rays.
#include <benchmark/benchmark.h>

#include <cmath>
#include <span>
#include <vector>

#include "cwe/envelope/linear_sweep.hpp"
#include "cwe/io/mesh_io.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "cwe/workpiece/dexel/dexel_mesh.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"

namespace {

const cwe::Aabb kBlock{{0, 0, 0}, {100, 100, 40}};

cwe::Move line(const cwe::Vec3& a, const cwe::Vec3& b) {
  cwe::Move m;
  m.start = a;
  m.end = b;
  m.start_axis = m.end_axis = cwe::Vec3::UnitZ();
  return m;
}

cwe::Toolpath pocket_job() {
  cwe::Toolpath path;
  for (double z = 37.0; z > 23.0; z -= 3.0) {
    for (double y = 10.0; y <= 90.0; y += 8.0) {
      const bool forward = static_cast<int>(std::lround((y - 10.0) / 8.0)) % 2 == 0;
      for (int k = 0; k < 80; ++k) {
        const double x0 = forward ? 10.0 + k : 90.0 - k, x1 = forward ? x0 + 1.0 : x0 - 1.0;
        path.moves.push_back(line({x0, y, z}, {x1, y, z}));
      }
      const double x = forward ? 90.0 : 10.0;
      if (y + 8.0 <= 90.0) path.moves.push_back(line({x, y, z}, {x, y + 8.0, z}));
    }
  }
  return path;
}

double surface(double x, double y) { return 32.0 + 4.0 * std::sin(x / 12.0) * std::cos(y / 17.0); }

cwe::Toolpath raster_job() {
  cwe::Toolpath path;
  for (int pass = 0; pass < 5; ++pass) {
    const double y = 20.0 + 0.5 * pass;
    for (int k = 0; k < 100; ++k) {
      const double x0 = pass % 2 == 0 ? k : 100 - k, x1 = pass % 2 == 0 ? x0 + 1 : x0 - 1;
      path.moves.push_back(line({x0, y, surface(x0, y)}, {x1, y, surface(x1, y)}));
    }
  }
  return path;
}

void report(benchmark::State& state, const cwe::TriDexel& stock, std::size_t moves) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * moves));
  const auto rays = static_cast<double>(stock.ray_count());
  state.counters["bytes_per_ray"] = static_cast<double>(stock.memory().total()) / rays;
  state.counters["peak_bytes_per_ray"] = static_cast<double>(stock.memory().peak()) / rays;
  state.counters["rays"] = rays;
}

void run_job(benchmark::State& state, const char* tool, const cwe::Toolpath& path) {
  const double spacing = static_cast<double>(state.range(0)) * 1e-3;
  const cwe::Cutter cutter = cwe::cutter_from_spec(tool);
  cwe::SimulationOptions options;
  options.resolution = spacing;
  cwe::TriDexel stock = cwe::TriDexel::from_box(kBlock, spacing);
  for (auto _ : state) {
    state.PauseTiming();
    stock = cwe::TriDexel::from_box(kBlock, spacing);
    state.ResumeTiming();
    benchmark::DoNotOptimize(cwe::remove_toolpath(stock, cutter, path, options));
  }
  report(state, stock, path.moves.size());
}

void BM_PocketJob(benchmark::State& state) { run_job(state, "flat:10,30", pocket_job()); }
BENCHMARK(BM_PocketJob)->Arg(100)->Arg(50)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PocketOneByOne(benchmark::State& state) {
  const double spacing = static_cast<double>(state.range(0)) * 1e-3;
  const cwe::Cutter cutter = cwe::cutter_from_spec("flat:10,30");
  const cwe::Toolpath path = pocket_job();
  cwe::TriDexel stock = cwe::TriDexel::from_box(kBlock, spacing);
  for (auto _ : state) {
    state.PauseTiming();
    stock = cwe::TriDexel::from_box(kBlock, spacing);
    state.ResumeTiming();
    for (const cwe::Move& move : path.moves) {
      const cwe::LinearSweep sweep(cutter, move.start, move.end, move.start_axis);
      // As the engagement's removal makes it: chords a row of rays at a time.
      const cwe::TriDexel::Cut cut{
          sweep.bounds(),
          [&sweep](const cwe::Ray& ray) { return sweep.chord(ray); },
          {},
          [&sweep](const cwe::Ray& ray, int across, std::span<const double> at,
                   std::span<cwe::Interval> chords) { sweep.chords(ray, across, at, chords); }};
      benchmark::DoNotOptimize(stock.remove({cut}));
    }
  }
  report(state, stock, path.moves.size());
}
BENCHMARK(BM_PocketOneByOne)->Arg(100)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BallRaster(benchmark::State& state) { run_job(state, "ball:6,20", raster_job()); }
BENCHMARK(BM_BallRaster)->Arg(100)->Arg(50)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BullRaster(benchmark::State& state) { run_job(state, "bull:10,2,20", raster_job()); }
BENCHMARK(BM_BullRaster)->Arg(100)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_StockBox(benchmark::State& state) {
  std::size_t rays = 0;
  for (auto _ : state) {
    const cwe::TriDexel stock = cwe::TriDexel::from_box(kBlock, 0.1);
    rays = stock.ray_count();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * rays));
}
BENCHMARK(BM_StockBox)->Unit(benchmark::kMillisecond)->UseRealTime();

// The block after PocketJob at s = 0.1, as `cwe simulate` contours it.
cwe::TriDexel pocketed_block() {
  cwe::TriDexel stock = cwe::TriDexel::from_box(kBlock, 0.1);
  cwe::remove_toolpath(stock, cwe::cutter_from_spec("flat:10,30"), pocket_job(), {});
  return stock;
}

void BM_PocketMesh(benchmark::State& state) {
  const cwe::TriDexel stock = pocketed_block();
  std::size_t triangles = 0;
  for (auto _ : state) {
    const cwe::TriangleMesh mesh = cwe::dexel_mesh(stock, 3);
    triangles = mesh.triangles.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * triangles));
}
BENCHMARK(BM_PocketMesh)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PocketStl(benchmark::State& state) {
  const cwe::TriangleMesh mesh = cwe::dexel_mesh(pocketed_block(), 3);
  std::size_t bytes = 0;
  for (auto _ : state) {
    bytes = 0;
    cwe::stl_binary_facets(mesh.triangles, mesh.vertices,
                           [&bytes](std::string_view piece) { bytes += piece.size(); });
    benchmark::DoNotOptimize(bytes);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * mesh.triangles.size()));
}
BENCHMARK(BM_PocketStl)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
