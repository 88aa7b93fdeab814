// Engagement and removal together (the main job): cutter locations per second at s = 0.1 mm, in
// a 100 × 100 × 40 mm block (the benchmark of the engagement issue). One iteration runs a whole
// job on a fresh stock (making the stock is not timed); items are cutter locations, wall time.
//  - PocketLevel: the first level of the tri-dexel pocketing job (10 mm flat end mill, 1 mm
//    zig-zag segments, 3 mm deep), CL every 0.5 mm;
//  - Finishing: a 6 mm ball end mill raster (1 mm segments along X, 0.5 mm stepover, five passes)
//    over a curved surface left 0.5 mm above it (the stock is that surface, read from a closed
//    mesh), CL every 0.3 mm.
// Counters: CL per second, engaged share, and the cost of the mechanistic force model per CL
// (1° spindle step, over the job's maps; timed apart from the job): force_us_per_cl against
// engagement_us_per_cl (the job's wall time per CL, removal included).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <vector>

#include "cwe/process/force_model.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"

namespace {

cwe::Move line(const cwe::Vec3& a, const cwe::Vec3& b) {
  cwe::Move m;
  m.start = a;
  m.end = b;
  m.feed_rate = 1000.0;
  return m;
}

double surface(double x, double y) { return 32.0 + 4.0 * std::sin(x / 12.0) * std::cos(y / 17.0); }

// The block below surface(x, y) + 0.5 as a closed mesh: a 1 mm grid on top, flat bottom at z 0.
cwe::TriangleMesh roughed_block() {
  cwe::TriangleMesh m;
  constexpr int n = 100;
  const auto top = [](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) m.vertices.emplace_back(i, j, surface(i, j) + 0.5);
  }
  const int base = static_cast<int>(m.vertices.size());
  for (const auto& corner :
       {cwe::Vec3(0, 0, 0), cwe::Vec3(n, 0, 0), cwe::Vec3(n, n, 0), cwe::Vec3(0, n, 0)}) {
    m.vertices.push_back(corner);
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({top(i, j), top(i + 1, j), top(i + 1, j + 1)});
      m.triangles.push_back({top(i, j), top(i + 1, j + 1), top(i, j + 1)});
    }
  }
  // Sides: each edge of the top grid down to the bottom corners, fanned from a corner.
  const auto side = [&](std::vector<int> rim, int c0, int c1) {  // rim runs from corner c0 to c1
    for (std::size_t k = 0; k + 1 < rim.size(); ++k)
      m.triangles.push_back({rim[k + 1], rim[k], c0});
    m.triangles.push_back({c1, rim.back(), c0});
  };
  std::vector<int> front, right, back, left;
  for (int i = 0; i <= n; ++i) front.push_back(top(i, 0));
  for (int j = 0; j <= n; ++j) right.push_back(top(n, j));
  for (int i = n; i >= 0; --i) back.push_back(top(i, n));
  for (int j = n; j >= 0; --j) left.push_back(top(0, j));
  side(front, base + 0, base + 1);
  side(right, base + 1, base + 2);
  side(back, base + 2, base + 3);
  side(left, base + 3, base + 0);
  m.triangles.push_back({base + 0, base + 2, base + 1});
  m.triangles.push_back({base + 0, base + 3, base + 2});
  return m;
}

void run(benchmark::State& state, const char* tool, const cwe::Toolpath& path, double cl_step,
         const std::function<cwe::TriDexel()>& make) {
  const cwe::Cutter cutter = cwe::cutter_from_spec(tool);
  cwe::SimulationOptions options;
  options.resolution = 0.1;
  cwe::SamplingOptions sampling;
  sampling.step = cl_step;
  std::size_t cls = 0, engaged = 0;
  std::vector<std::pair<cwe::EngagementMap, cwe::ToolState>> maps;
  const auto started = std::chrono::steady_clock::now();
  for (auto _ : state) {
    state.PauseTiming();
    cwe::TriDexel stock = make();
    cls = engaged = 0;
    maps.clear();
    state.ResumeTiming();
    cwe::simulate_engagement(stock, cutter, path, {options, sampling, {}},
                             [&](const cwe::ClEngagement& e) {
                               ++cls;
                               engaged += e.map.engaged ? 1 : 0;
                               maps.emplace_back(e.map, e.state);
                             });
  }
  const double job_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  // The force model over the same maps (Al7075-like coefficients, 0.05 mm per tooth).
  cwe::CuttingCoefficients k;
  k.ktc = 796.0, k.krc = 168.8, k.kac = 222.0, k.kte = 27.7, k.kre = 30.8, k.kae = 1.8;
  const cwe::ForceModel model(cutter, k);
  const auto forces_started = std::chrono::steady_clock::now();
  double sink = 0.0;
  for (const auto& [map, at] : maps) sink += model.evaluate(map, at, 0.05, 10000.0).mean_torque;
  const double force_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - forces_started).count();
  benchmark::DoNotOptimize(sink);
  if (cls > 0) {
    state.counters["force_us_per_cl"] = 1e6 * force_seconds / static_cast<double>(cls);
    state.counters["engagement_us_per_cl"] =
        1e6 * job_seconds / static_cast<double>(cls * state.iterations());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * cls));
  state.counters["cl_points"] = static_cast<double>(cls);
  state.counters["engaged_share"] =
      cls > 0 ? static_cast<double>(engaged) / static_cast<double>(cls) : 0.0;
}

void BM_PocketLevel(benchmark::State& state) {
  cwe::Toolpath path;
  for (double y = 10.0; y <= 90.0; y += 8.0) {
    const bool forward = static_cast<int>(std::lround((y - 10.0) / 8.0)) % 2 == 0;
    for (int k = 0; k < 80; ++k) {
      const double x0 = forward ? 10.0 + k : 90.0 - k, x1 = forward ? x0 + 1.0 : x0 - 1.0;
      path.moves.push_back(line({x0, y, 37.0}, {x1, y, 37.0}));
    }
    const double x = forward ? 90.0 : 10.0;
    if (y + 8.0 <= 90.0) path.moves.push_back(line({x, y, 37.0}, {x, y + 8.0, 37.0}));
  }
  run(state, "flat:10,30", path, 0.5, [] {
    return cwe::TriDexel::from_box(cwe::Aabb{{0, 0, 0}, {100, 100, 40}}, 0.1);
  });
}
BENCHMARK(BM_PocketLevel)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_Finishing(benchmark::State& state) {
  cwe::Toolpath path;
  for (int pass = 0; pass < 5; ++pass) {
    const double y = 20.0 + 0.5 * pass;
    for (int k = 0; k < 100; ++k) {
      const double x0 = pass % 2 == 0 ? k : 100 - k, x1 = pass % 2 == 0 ? x0 + 1 : x0 - 1;
      path.moves.push_back(line({x0, y, surface(x0, y)}, {x1, y, surface(x1, y)}));
    }
  }
  const cwe::TriangleMesh block = roughed_block();
  run(state, "ball:6,20", path, 0.3,
      [&block] { return cwe::TriDexel::from_mesh(block, 0.1, "roughed block"); });
}
BENCHMARK(BM_Finishing)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
