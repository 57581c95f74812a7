// Per-call cost of parallel_for (core/parallel.hpp) on its persistent pool: a 256-item loop with
// a trivial body, so the figure is the fork/join overhead, compared with a plain serial loop and
// with starting std::threads per call (what parallel_for did before the pool).
#include <benchmark/benchmark.h>

#include <fabsynth/core/parallel.hpp>

#include <thread>
#include <vector>

static void BM_parallel_for_256(benchmark::State& state) {
    const unsigned threads = static_cast<unsigned>(state.range(0));
    std::vector<double> v(256, 1.0);
    for (auto _ : state) {
        fabsynth::parallel_for(0, v.size(), [&](std::size_t i) { v[i] = v[i] * 1.0000001 + 1e-9; }, {.grain = 16, .threads = threads});
        benchmark::DoNotOptimize(v.data());
    }
}
BENCHMARK(BM_parallel_for_256)->Arg(1)->Arg(2)->UseRealTime();

static void BM_parallel_reduce_256(benchmark::State& state) {
    const unsigned threads = static_cast<unsigned>(state.range(0));
    for (auto _ : state) {
        double s = fabsynth::parallel_reduce(0, 256, 0.0, [](std::size_t i) { return double(i); }, std::plus<>{},
                                             {.grain = 16, .threads = threads});
        benchmark::DoNotOptimize(s);
    }
}
BENCHMARK(BM_parallel_reduce_256)->Arg(1)->Arg(2)->UseRealTime();

// Baseline: one std::jthread started and joined per call (the pre-pool parallel_for on 2 threads).
static void BM_thread_per_call_256(benchmark::State& state) {
    std::vector<double> v(256, 1.0);
    for (auto _ : state) {
        {
            std::jthread t([&] { for (std::size_t i = 128; i < 256; ++i) v[i] = v[i] * 1.0000001 + 1e-9; });
            for (std::size_t i = 0; i < 128; ++i) v[i] = v[i] * 1.0000001 + 1e-9;
        }
        benchmark::DoNotOptimize(v.data());
    }
}
BENCHMARK(BM_thread_per_call_256)->UseRealTime();
