// What the machine gives a second thread, to read the job's thread speed-up against: the same
// loop on one thread and on two at once, each thread doing the iterations one thread does
// (Google Benchmark's Threads(n)), so that a time per iteration that grows from one thread to
// two is what the threads take from each other.
//  - BM_Arithmetic: a chain of integer multiplies and adds in registers. Two cores of their own
//    run it side by side at the speed of one; two hardware threads of one core do not.
//  - BM_DependentLoads/bytes: a walk along a random cycle through an array of `bytes`, each load
//    waiting for the one before (the stock's rays and the records are read so, a little at a
//    time). Below the L2 cache it measures the core alone; beyond it, the last-level cache and
//    the memory the threads (and, on a virtual machine, other guests) share.
//  - BM_HandOff: two threads passing one cache line back and forth, each waiting for the other's
//    write before writing: the time a round trip takes is what data made on one core costs the
//    other (a removed step's record read by the engagement search, a stock ray written after the
//    other thread wrote it). Cores that share a cache pass it in tens of nanoseconds; cores on
//    different dies, or on a virtual machine, take several times that.
// Run: build/bench/host_bench (docs/performance.md, fourteenth pass, gives figures).

#include <benchmark/benchmark.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <random>
#include <thread>
#include <utility>
#include <vector>

namespace {

constexpr std::int64_t kSteps = 1 << 22;

void BM_Arithmetic(benchmark::State& state) {
  std::uint64_t x = 1, y = 3;
  for (auto _ : state) {
    for (std::int64_t k = 0; k < kSteps; ++k) {
      x = x * 6364136223846793005u + y;
      y ^= x >> 17;
    }
    benchmark::DoNotOptimize(x);
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}
BENCHMARK(BM_Arithmetic)->Threads(1)->Threads(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// A single cycle through all n slots (Sattolo's shuffle), so that the walk visits every one.
std::vector<std::uint32_t> random_cycle(std::size_t n, std::uint32_t seed) {
  std::vector<std::uint32_t> next(n);
  std::iota(next.begin(), next.end(), 0u);
  std::mt19937 random(seed);
  for (std::size_t i = n - 1; i > 0; --i) {
    std::uniform_int_distribution<std::size_t> pick(0, i - 1);
    std::swap(next[i], next[pick(random)]);
  }
  return next;
}

void BM_DependentLoads(benchmark::State& state) {
  // Each thread walks an array of its own.
  const std::vector<std::uint32_t> next =
      random_cycle(static_cast<std::size_t>(state.range(0)) / sizeof(std::uint32_t),
                   static_cast<std::uint32_t>(state.thread_index() + 1));
  std::uint32_t at = 0;
  for (auto _ : state) {
    for (std::int64_t k = 0; k < kSteps; ++k) at = next[at];
    benchmark::DoNotOptimize(at);
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}
BENCHMARK(BM_DependentLoads)
    ->Arg(1 << 20)
    ->Arg(8 << 20)
    ->Arg(64 << 20)
    ->Threads(1)
    ->Threads(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The line both threads pass: thread 0 writes the odd values, thread 1 the even ones, each
// after reading the value before its own.
alignas(64) std::atomic<std::uint64_t> turn{0};

void BM_HandOff(benchmark::State& state) {
  constexpr std::int64_t kRoundTrips = 1 << 14;
  constexpr int kSpins = 1 << 12;
  const auto me = static_cast<std::uint64_t>(state.thread_index());
  if (me == 0) turn.store(0, std::memory_order_relaxed);  // before the threads start together
  std::uint64_t value = me;                               // the value this thread waits for next
  for (auto _ : state) {
    for (std::int64_t k = 0; k < kRoundTrips; ++k, value += 2) {
      // A few microseconds of spinning is far beyond a hand-off between running cores; past it
      // the other thread is not running (one CPU, or its vCPU descheduled): give way to it.
      for (int spins = 0; turn.load(std::memory_order_acquire) != value; ++spins) {
        if (spins > kSpins) std::this_thread::yield();
      }
      turn.store(value + 1, std::memory_order_release);
    }
  }
  if (me == 0) {
    state.SetItemsProcessed(state.iterations() * kRoundTrips);
    state.counters["round_trip"] =
        benchmark::Counter(static_cast<double>(state.iterations() * kRoundTrips),
                           benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  }
}
BENCHMARK(BM_HandOff)->Threads(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
