// Throughput of the G-code reader (RS274NGC as LinuxCNC runs it, docs/gcode.md), in program lines
// read per second (items) and moves made. One iteration reads a whole program held in memory.
//  - StraightLines: N lines of "G1 X… Y… Z…" as CAM posts write them;
//  - Loop: a while loop whose 4-line body computes each point with parameters and expressions
//    and makes one move; N counts executed lines (N/4 moves);
//  - Arcs: N lines alternating G2 and G3 quarter arcs, IJK;
//  - StraightLinesStreamed: StraightLines with each move handed to a sink instead of kept (how
//    `cwe path` reads; bench/gcode_memory.sh measures its memory on 10 million lines).
// Compare with LinuxCNC's librs274 measured the same way: docs/gcode.md, "Why cwe has its own
// interpreter".
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "cwe/toolpath/gcode_reader.hpp"

namespace {

std::string straight_lines(int n) {
  std::string text = "G21 G90 G17 F600\nG0 X0 Y0 Z5\n";
  for (int k = 0; k < n; ++k) {
    text += fmt::format("G1 X{:.4f} Y{:.4f} Z{:.4f}\n", 0.01 * k, 0.5 * (k % 100), -0.001 * (k % 7));
  }
  return text + "M2\n";
}

std::string loop(int iterations) {
  return fmt::format(
      "G21 G90 F600\n#1 = 0\no100 while [#1 LT {}]\n"
      "  #2 = [#1 * 0.01]\n  G1 X#2 Y[SIN[#1] * 10] Z[-1 - [#1 MOD 5] * 0.1]\n"
      "  #1 = [#1 + 1]\no100 endwhile\nM2\n",
      iterations);
}

std::string arcs(int n) {
  std::string text = "G21 G90 G17 F600\nG0 X10 Y0 Z0\n";
  for (int k = 0; k < n; ++k) {
    // Quarter circles of radius 10 about the origin, back and forth.
    text += k % 2 == 0 ? "G3 X0 Y10 I-10 J0\n" : "G2 X10 Y0 I0 J-10\n";
  }
  return text + "M2\n";
}

void run(benchmark::State& state, const std::string& text, double lines) {
  std::size_t moves = 0;
  for (auto _ : state) moves = cwe::read_gcode(text, "bench.ngc").moves.size();
  state.SetItemsProcessed(
      static_cast<std::int64_t>(static_cast<double>(state.iterations()) * lines));
  state.counters["moves"] = static_cast<double>(moves);
}

void BM_StraightLines(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  run(state, straight_lines(n), n);
}
BENCHMARK(BM_StraightLines)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_Loop(benchmark::State& state) {
  const int iterations = static_cast<int>(state.range(0)) / 4;
  run(state, loop(iterations), 4.0 * iterations);
}
BENCHMARK(BM_Loop)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_Arcs(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  run(state, arcs(n), n);
}
BENCHMARK(BM_Arcs)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_StraightLinesStreamed(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const std::string text = straight_lines(n);
  std::size_t moves = 0;
  const cwe::MoveSink sink = [&](const cwe::Move&, const std::vector<std::string>&) { ++moves; };
  for (auto _ : state) {
    moves = 0;
    cwe::read_gcode(text, "bench.ngc", {}, sink);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * n);
  state.counters["moves"] = static_cast<double>(moves);
}
BENCHMARK(BM_StraightLinesStreamed)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace
