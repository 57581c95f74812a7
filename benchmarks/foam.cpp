// Procedural Voronoi foam throughput (issue 4): exact tiled slicer on 1 and 2 threads, the paper's
// Algorithm 1 as a baseline on a 100 x 100 sub-slice, and random-access point evaluation; issue 17:
// per-point queries in row order, at random, in a batch, next to a cellular-noise reference.
// Configuration: 1000 x 1000 slice at 0.05 mm pixels (50 x 50 mm), tau = 0.25 mm, density graded
// linearly in x from 0.01 to 0.5 seeds/mm^3, coarse cell 5 mm (so 0.01 is above the 1/L^3 clamp).
// Every benchmark reports items_per_second (pixels or points); BM_FoamSliceExact_100x100 also
// reports speedup_vs_algorithm1, the exact slicer's pixels/s over Algorithm 1's points/s on the
// same sub-slice, both on one thread and in process CPU time (so a loaded machine affects both
// alike).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <vector>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/core/rng.hpp"
#include "fabsynth/foam/evaluator.hpp"
#include "fabsynth/foam/field_adaptors.hpp"

using namespace fabsynth;
using namespace fabsynth::foam;

namespace {

const voronoi_foam<linear_field, constant_field>& bench_foam() {
    static const voronoi_foam f(linear_field{0, 0.01, 0.5, 0, 50}, constant_field{0.25}, {.cell = 5, .seed = 2016});
    return f;
}

// The paper's Algorithm 1 + 2, written plainly: gather the seeds of the 2-ring of coarse cells around
// q's cell and around the closest seed's cell, then for every pair (i, j) test the equidistant line of
// (N0, Ni, Nj). The accept test uses a relative tolerance and skips the two seeds defining the line.
bool algorithm1(const voronoi_foam<linear_field, constant_field>& f, const vec3& q, double tau,
                std::vector<vec3>& N, std::vector<i64vec3>& visited) {
    const double L = f.options().cell;
    N.clear();
    visited.clear();
    auto ring = [&](const i64vec3& c) {
        for (std::int64_t z = -2; z <= 2; ++z)
            for (std::int64_t y = -2; y <= 2; ++y)
                for (std::int64_t x = -2; x <= 2; ++x) {
                    const i64vec3 k = c + i64vec3(x, y, z);
                    if (std::find(visited.begin(), visited.end(), k) != visited.end()) continue;
                    visited.push_back(k);
                    f.seeds().cell_seeds(k, N);
                }
    };
    ring(coarse_cell_of(q, L));
    std::size_t best = 0;
    for (std::size_t i = 1; i < N.size(); ++i)
        if (glm::length(N[i] - q) < glm::length(N[best] - q)) best = i;
    std::swap(N[0], N[best]);
    ring(coarse_cell_of(N[0], L));
    const vec3 s0 = N[0];
    for (std::size_t i = 1; i < N.size(); ++i)
        for (std::size_t j = i + 1; j < N.size(); ++j) {
            const vec3 n1 = N[i] - s0, n2 = N[j] - s0, d = glm::cross(n1, n2);
            const double dl2 = glm::dot(d, d);
            if (dl2 == 0) continue;
            const vec3 u = d / std::sqrt(dl2);
            const double r1 = 0.5 * (glm::dot(N[i], N[i]) - glm::dot(s0, s0));
            const double r2 = 0.5 * (glm::dot(N[j], N[j]) - glm::dot(s0, s0));
            const double r3 = glm::dot(u, s0);
            const double det = glm::dot(n1, glm::cross(n2, u));
            const vec3 p0 = (r1 * glm::cross(n2, u) + r2 * glm::cross(u, n1) + r3 * glm::cross(n1, n2)) / det;
            const vec3 pl = p0 + glm::dot(q - p0, u) * u;  // closest point of the line to q
            if (glm::length(q - pl) > tau) continue;
            const double d0 = glm::length(s0 - pl);
            bool accept = true;
            for (std::size_t k = 1; k < N.size() && accept; ++k)
                if (k != i && k != j && d0 > glm::length(N[k] - pl) * (1 + 1e-9)) accept = false;
            if (accept) return true;
        }
    return false;
}

void BM_FoamSlice_1000x1000(benchmark::State& state) {
    const auto& f = bench_foam();
    set_num_threads(static_cast<unsigned>(state.range(0)));
    double z = 20;
    for (auto _ : state) {
        image8 img = f.slice(z, {{0, 0}, {50, 50}}, 0.05);
        benchmark::DoNotOptimize(img.data.data());
        z += 0.05;  // a fresh layer every iteration, like a printer
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * 1000000);
    state.counters["threads"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_FoamSlice_1000x1000)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// A stack of 200 slices at 0.05 mm through the same 50 x 50 mm region (for_each_slice: the edges
// of each tile column built once per slab of one 5 mm cell), streamed to a sink.
void BM_FoamSliceStack_1000x1000(benchmark::State& state) {
    const auto& f = bench_foam();
    set_num_threads(static_cast<unsigned>(state.range(0)));
    std::vector<double> zs(200);
    for (std::size_t k = 0; k < zs.size(); ++k) zs[k] = 20 + 0.05 * static_cast<double>(k);
    for (auto _ : state) {
        long solid = 0;
        f.for_each_slice(zs, {{0, 0}, {50, 50}}, 0.05, [&](std::size_t, image8& img) { solid += img.data[img.data.size() / 2]; });
        benchmark::DoNotOptimize(solid);
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * 200 * 1000000);
}
BENCHMARK(BM_FoamSliceStack_1000x1000)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Same 100 x 100 sub-slice for both: at the sparse end (x in [0, 5] mm), where Algorithm 1 gathers
// the fewest seeds; elsewhere it is slower still. Algorithm 1 takes ~20 ms per point here, so it
// runs on every 4th pixel of the sub-slice in x and y (625 points, ~15 s); it also counts how
// often it disagrees with the exact evaluator (counter "disagree"; expected 0).
double algorithm1_points_per_second = 0;  // set by the baseline, read by the exact sub-slice benchmark

double cpu_seconds() {  // process CPU time (all threads)
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

vec3 subslice_pixel(int i, int j) { return vec3((i + 0.5) * 0.05, 20 + (j + 0.5) * 0.05, 20.0); }

double run_algorithm1(int stride, long& solid, long& disagree) {
    const auto& f = bench_foam();
    std::vector<vec3> N;
    std::vector<i64vec3> visited;
    long points = 0;
    const double t0 = cpu_seconds();
    for (int j = 0; j < 100; j += stride)
        for (int i = 0; i < 100; i += stride) {
            const bool s = algorithm1(f, subslice_pixel(i, j), 0.25, N, visited);
            solid += s;
            disagree += s != f.contains(subslice_pixel(i, j));  // contains() is < 1% of the time
            ++points;
        }
    return static_cast<double>(points) / (cpu_seconds() - t0);
}

void BM_FoamSliceAlgorithm1Baseline_100x100(benchmark::State& state) {
    long solid = 0, disagree = 0;
    double rate = 0;
    for (auto _ : state) rate = run_algorithm1(4, solid, disagree);
    benchmark::DoNotOptimize(solid);
    algorithm1_points_per_second = rate;
    state.SetItemsProcessed(state.iterations() * 625);
    state.counters["disagree"] = static_cast<double>(disagree);
    state.counters["solid"] = static_cast<double>(solid);
}
BENCHMARK(BM_FoamSliceAlgorithm1Baseline_100x100)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_FoamSliceExact_100x100(benchmark::State& state) {
    const auto& f = bench_foam();
    if (algorithm1_points_per_second == 0) {  // baseline filtered out: a short measurement instead
        long solid = 0, disagree = 0;
        algorithm1_points_per_second = run_algorithm1(20, solid, disagree);
    }
    set_num_threads(1);
    double sec = 0;
    for (auto _ : state) {
        const double t0 = cpu_seconds();
        image8 img = f.slice(20.0, {{0, 20}, {5, 25}}, 0.05);
        benchmark::DoNotOptimize(img.data.data());
        sec += cpu_seconds() - t0;
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * 10000);
    // (exact pixels / s) / (Algorithm 1 points / s), same sub-slice, one thread each
    state.counters["speedup_vs_algorithm1"] =
        static_cast<double>(state.iterations()) * 10000 / sec / algorithm1_points_per_second;
    state.counters["algorithm1_points_per_s"] = algorithm1_points_per_second;
}
BENCHMARK(BM_FoamSliceExact_100x100)->Unit(benchmark::kMillisecond);

void BM_FoamPointRandom(benchmark::State& state) {
    const auto& f = bench_foam();
    counter_rng rng(42, 0);
    long solid = 0;
    for (auto _ : state) {
        const vec3 q(rng.uniform(0, 50), rng.uniform(0, 50), rng.uniform(0, 50));
        solid += f.contains(q);
    }
    benchmark::DoNotOptimize(solid);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FoamPointRandom);

// ---- issue 17: per-point queries at cellular-noise speed -------------------------------------
// Configuration of the issue: a 400 x 400 pixel grid at 0.05 mm, density graded 0.02 -> 0.4
// seeds/mm^3 over 20 mm, tau 0.25 mm, cell 4 mm; random points in a 40 mm cube. Arg = threads.

const voronoi_foam<linear_field, constant_field>& point_foam() {
    static const voronoi_foam f(linear_field{0, 0.02, 0.4, 0, 20}, constant_field{0.25}, {.cell = 4, .seed = 2016});
    return f;
}

const std::vector<vec3>& cube_points() {
    static const std::vector<vec3> pts = [] {
        std::vector<vec3> p;
        counter_rng rng(17, 0);
        for (int i = 0; i < 1000000; ++i) p.push_back(vec3(rng.uniform(0, 40), rng.uniform(0, 40), rng.uniform(0, 40)));
        return p;
    }();
    return pts;
}

// contains() pixel by pixel in row order, rows spread over the threads.
void BM_FoamPointRowOrder(benchmark::State& state) {
    set_num_threads(static_cast<unsigned>(state.range(0)));
    const auto& f = point_foam();
    std::vector<long> solid(400);
    for (auto _ : state) {
        parallel_for(0, 400, [&](std::size_t j) {
            long n = 0;
            for (int i = 0; i < 400; ++i) n += f.contains(vec3(0.025 + 0.05 * i, 0.025 + 0.05 * static_cast<double>(j), 10.0));
            solid[j] = n;
        });
        benchmark::DoNotOptimize(solid.data());
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * 160000);
}
BENCHMARK(BM_FoamPointRowOrder)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// contains() at random points of a 40 mm cube, one call per point, points split over the threads.
void BM_FoamPointRandomCube(benchmark::State& state) {
    set_num_threads(static_cast<unsigned>(state.range(0)));
    const auto& f = point_foam();
    const auto& pts = cube_points();
    std::vector<long> solid(64);
    auto pass = [&] {  // 64 runs of consecutive points (each a random position)
        parallel_for(0, 64, [&](std::size_t c) {
            long n = 0;
            for (std::size_t i = c * pts.size() / 64; i < (c + 1) * pts.size() / 64; ++i) n += f.contains(pts[i]);
            solid[c] = n;
        });
    };
    pass();  // warm: every thread's cache holds the cube's blocks (1000 blocks of a 4 mm cell)
    for (auto _ : state) {
        pass();
        benchmark::DoNotOptimize(solid.data());
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * static_cast<long>(pts.size()));
}
BENCHMARK(BM_FoamPointRandomCube)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

// The batch API on the same random points (sorted by block inside).
void BM_FoamPointBatch(benchmark::State& state) {
    set_num_threads(static_cast<unsigned>(state.range(0)));
    const auto& f = point_foam();
    const auto& pts = cube_points();
    std::vector<std::uint8_t> out(pts.size());
    for (auto _ : state) {
        f.contains(pts, out);
        benchmark::DoNotOptimize(out.data());
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * static_cast<long>(pts.size()));
}
BENCHMARK(BM_FoamPointBatch)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

// The same batch through the field type chosen at run time, as foam_slicer and the Python package's
// Foam hold it (a variant of constant and ramp, inside a variant with the elasticity mapping): the
// C++ side of benchmarks/python_contains.py, which measures the binding's overhead on top of it.
void BM_FoamPointBatchRuntimeField(benchmark::State& state) {
    using value_field = variant_field<constant_field, linear_field>;
    using density_field = variant_field<value_field, elasticity_density_field<value_field>>;
    static const voronoi_foam f(density_field{value_field{linear_field{0, 0.02, 0.4, 0, 20}}}, constant_field{0.25}, {.cell = 4, .seed = 2016});
    set_num_threads(static_cast<unsigned>(state.range(0)));
    const auto& pts = cube_points();
    std::vector<std::uint8_t> out(pts.size());
    f.contains(pts, out);  // warm, as the Python script does before timing
    for (auto _ : state) {
        f.contains(pts, out);
        benchmark::DoNotOptimize(out.data());
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * static_cast<long>(pts.size()));
}
BENCHMARK(BM_FoamPointBatchRuntimeField)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

// The grid as one slice, and as a stack of 200 slices at 0.05 mm (for_each_slice).
void BM_FoamPointGridSlice(benchmark::State& state) {
    set_num_threads(static_cast<unsigned>(state.range(0)));
    const auto& f = point_foam();
    double z = 10;
    for (auto _ : state) {
        image8 img = f.slice(z, {{0, 0}, {20, 20}}, 0.05);
        benchmark::DoNotOptimize(img.data.data());
        z += 0.05;
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * 160000);
}
BENCHMARK(BM_FoamPointGridSlice)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FoamPointGridStack(benchmark::State& state) {
    set_num_threads(static_cast<unsigned>(state.range(0)));
    const auto& f = point_foam();
    std::vector<double> zs(200);
    for (std::size_t k = 0; k < zs.size(); ++k) zs[k] = 10 + 0.05 * static_cast<double>(k);
    for (auto _ : state) {
        long solid = 0;
        f.for_each_slice(zs, {{0, 0}, {20, 20}}, 0.05, [&](std::size_t, image8& img) { solid += img.data[img.data.size() / 2]; });
        benchmark::DoNotOptimize(solid);
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * 200 * 160000);
}
BENCHMARK(BM_FoamPointGridStack)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// contains_uncached(): the pieces of the query's own small cube (what a cache miss costs).
void BM_FoamPointUncached(benchmark::State& state) {
    const auto& f = point_foam();
    const auto& pts = cube_points();
    std::size_t i = 0;
    long solid = 0;
    for (auto _ : state) solid += f.contains_uncached(pts[i++ % pts.size()]);
    benchmark::DoNotOptimize(solid);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FoamPointUncached)->Unit(benchmark::kMillisecond);

// The reference an embedder compares with: 3D cellular noise F2 - F1 (Euclidean) on a jittered
// grid, one feature point per unit cell, 27-cell search, written here (FastNoiseLite is not in
// Debian; this is the same algorithm, not its code), on the same 400 x 400 grid at a frequency
// of 0.25 / mm (a 4 mm feature cell, the foam's coarse cell).
float cellular_f2_minus_f1(double x, double y, double z) {
    const int xi = static_cast<int>(std::floor(x)), yi = static_cast<int>(std::floor(y)), zi = static_cast<int>(std::floor(z));
    double f1 = 1e9, f2 = 1e9;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const std::uint64_t h = hash64(1337, xi + dx, yi + dy, zi + dz);
                const double px = xi + dx + static_cast<double>(h & 0xffff) / 65536.0, py = yi + dy + static_cast<double>((h >> 16) & 0xffff) / 65536.0,
                             pz = zi + dz + static_cast<double>((h >> 32) & 0xffff) / 65536.0;
                const double d = (px - x) * (px - x) + (py - y) * (py - y) + (pz - z) * (pz - z);
                if (d < f1) f2 = f1, f1 = d;
                else if (d < f2) f2 = d;
            }
    return static_cast<float>(std::sqrt(f2) - std::sqrt(f1));
}

void BM_CellularNoiseReference(benchmark::State& state) {
    set_num_threads(static_cast<unsigned>(state.range(0)));
    std::vector<double> sums(400);
    for (auto _ : state) {
        parallel_for(0, 400, [&](std::size_t j) {
            double s = 0;
            for (int i = 0; i < 400; ++i) s += cellular_f2_minus_f1(0.25 * (0.025 + 0.05 * i), 0.25 * (0.025 + 0.05 * static_cast<double>(j)), 2.5);
            sums[j] = s;
        });
        benchmark::DoNotOptimize(sums.data());
    }
    set_num_threads(0);
    state.SetItemsProcessed(state.iterations() * 160000);
}
BENCHMARK(BM_CellularNoiseReference)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// ---- cold point queries: one pass over 20 000 random points of the 40 mm cube with a fresh foam
// (new per-thread cache entries: nothing held), then the same points again (warm), and a working
// set of seeds twice the seed cache (point_cache_bytes / 8, detail/near_seeds.hpp). Arg: 0 = the
// issue's graded foam, 1 = uniform 0.4 seeds/mm^3, 2 = steeply graded 0.02 -> 0.6 over 4 mm.
voronoi_foam<linear_field, constant_field> cold_foam(int kind, std::uint64_t seed, std::size_t budget) {
    const linear_field rho = kind == 0 ? linear_field{0, 0.02, 0.4, 0, 20} : kind == 1 ? linear_field{0, 0.4, 0.4, 0, 1} : linear_field{0, 0.02, 0.6, 18, 22};
    return voronoi_foam(rho, constant_field{0.25}, {.cell = 4, .seed = seed, .point_cache_bytes = budget});
}

const std::vector<vec3>& cold_points() {
    static const std::vector<vec3> pts(cube_points().begin(), cube_points().begin() + 20000);
    return pts;
}

void BM_FoamPointColdPass(benchmark::State& state) {
    const auto& pts = cold_points();
    std::uint64_t seed = 1;
    long solid = 0;
    for (auto _ : state) {
        state.PauseTiming();
        const auto f = cold_foam(static_cast<int>(state.range(0)), 2016 + seed++, std::size_t(128) << 20);
        state.ResumeTiming();
        for (const vec3& q : pts) solid += f.contains(q);
    }
    benchmark::DoNotOptimize(solid);
    state.SetItemsProcessed(state.iterations() * static_cast<long>(pts.size()));
}
BENCHMARK(BM_FoamPointColdPass)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_FoamPointWarmPass(benchmark::State& state) {
    const auto& pts = cold_points();
    const auto f = cold_foam(static_cast<int>(state.range(0)), 2016, std::size_t(128) << 20);
    long solid = 0;
    for (const vec3& q : pts) solid += f.contains(q);  // warm-up: one pass
    for (auto _ : state)
        for (const vec3& q : pts) solid += f.contains(q);
    benchmark::DoNotOptimize(solid);
    state.SetItemsProcessed(state.iterations() * static_cast<long>(pts.size()));
}
BENCHMARK(BM_FoamPointWarmPass)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The seed working set of the 20 000 points (measured on the foam of the warm pass: 2.1-2.4 MB of
// extended cells, 2 x 2 x 2 coarse cells each, for the three foams; 5-6 MB when an extended cell
// covered one coarse cell) is twice the seed cache: point_cache_bytes = 8 x half of it.
void BM_FoamPointTwiceBudget(benchmark::State& state) {
    const auto& pts = cold_points();
    const std::size_t working = std::size_t(2) << 20;
    const auto f = cold_foam(static_cast<int>(state.range(0)), 2016, 8 * (working / 2));
    long solid = 0;
    for (const vec3& q : pts) solid += f.contains(q);
    for (auto _ : state)
        for (const vec3& q : pts) solid += f.contains(q);
    benchmark::DoNotOptimize(solid);
    state.SetItemsProcessed(state.iterations() * static_cast<long>(pts.size()));
}
BENCHMARK(BM_FoamPointTwiceBudget)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace
