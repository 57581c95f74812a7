// Sampling block: the Poisson-disk radius search of structurally-sound-patterns.md §5.1 (1000
// samples from 10^5 and 10^6 points in a cube, 1 and 2 threads), and the medial axis of a bundled
// filigree element (the stroked polylines of data/filigree/leaf.svg turned into their outline by a
// Clipper round offset of half the stroke width) and of a synthetic wavy strip.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <polyclipping/clipper.hpp>

#include "fabsynth/core/parallel.hpp"
#include "fabsynth/geometry/clip.hpp"
#include "fabsynth/geometry/medial_axis.hpp"
#include "fabsynth/io/svg.hpp"
#include "fabsynth/sampling/poisson_disk.hpp"

namespace {

std::vector<fabsynth::vec3> cube_points(std::size_t n) {
    std::mt19937_64 g(42);
    std::uniform_real_distribution<double> u(0.0, 100.0);
    std::vector<fabsynth::vec3> pts(n);
    for (auto& p : pts) p = {u(g), u(g), u(g)};
    return pts;
}

// Args: {points, threads}. Items = candidate points per search.
void BM_PoissonDiskCount(benchmark::State& state) {
    const auto pts = cube_points(static_cast<std::size_t>(state.range(0)));
    fabsynth::set_num_threads(static_cast<unsigned>(state.range(1)));
    fabsynth::sampling::poisson_disk_count_result r;
    for (auto _ : state) {
        r = fabsynth::sampling::poisson_disk_count(pts, 1000, {.seed = 1});
        benchmark::DoNotOptimize(r.indices.data());
    }
    fabsynth::set_num_threads(0);
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * state.range(0));
    state.counters["samples"] = static_cast<double>(r.indices.size());
    state.counters["radii_tried"] = r.evaluations;
}

// One greedy pass at the radius the search ends with (the unit of work of the search).
void BM_PoissonDiskOneRadius(benchmark::State& state) {
    const auto pts = cube_points(static_cast<std::size_t>(state.range(0)));
    fabsynth::set_num_threads(static_cast<unsigned>(state.range(1)));
    const double r = fabsynth::sampling::poisson_disk_count(pts, 1000, {.seed = 1}).radius;
    for (auto _ : state) benchmark::DoNotOptimize(fabsynth::sampling::poisson_disk(pts, r, {.seed = 1}).data());
    fabsynth::set_num_threads(0);
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * state.range(0));
}

// The filigree leaf's outline: union of the strokes (round caps and joins) as polygons with holes.
fabsynth::polygon_with_holes leaf_outline() {
    const auto doc = fabsynth::io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/filigree/leaf.svg", {.tolerance = 0.01});
    double half_width = 0.5;
    std::vector<std::vector<fabsynth::vec2>> lines;
    for (const auto& s : doc.shapes) {
        half_width = 0.5 * s.stroke_width;
        lines.insert(lines.end(), s.subpaths.begin(), s.subpaths.end());
    }
    const auto polys = fabsynth::stroke_outline(lines, half_width, 0.01);  // arcs to 0.01 mm
    std::size_t best = 0;
    for (std::size_t i = 1; i < polys.size(); ++i)
        if (fabsynth::area(polys[i]) > fabsynth::area(polys[best])) best = i;
    return polys.at(best);
}

fabsynth::polygon_with_holes wavy_strip(int n) {
    fabsynth::ring2 upper, lower;
    for (int k = 0; k <= n; ++k) {
        const double x = 100.0 * k / n, y = 5.0 * std::sin(x / 5.0), w = 1.0 + 0.3 * std::cos(x / 3.0);
        upper.push_back({x, y + w});
        lower.push_back({x, y - w});
    }
    fabsynth::ring2 outer(lower.begin(), lower.end());
    outer.insert(outer.end(), upper.rbegin(), upper.rend());
    return {outer, {}};
}

void run_medial_axis(benchmark::State& state, const fabsynth::polygon_with_holes& poly, double prune) {
    std::size_t vertices = poly.outer.size();
    for (const auto& h : poly.holes) vertices += h.size();
    fabsynth::medial_skeleton sk;
    for (auto _ : state) {
        sk = fabsynth::medial_axis(poly, {.flattening_tolerance = 0.01, .prune_length = prune});
        benchmark::DoNotOptimize(sk.positions.data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * vertices));
    state.counters["boundary_vertices"] = static_cast<double>(vertices);
    state.counters["skeleton_vertices"] = static_cast<double>(sk.positions.size());
}

void BM_MedialAxisLeaf(benchmark::State& state) { run_medial_axis(state, leaf_outline(), 1.0); }
void BM_MedialAxisWavyStrip(benchmark::State& state) { run_medial_axis(state, wavy_strip(static_cast<int>(state.range(0))), 2.0); }

}  // namespace

BENCHMARK(BM_PoissonDiskCount)->Args({100000, 1})->Args({100000, 2})->Args({1000000, 1})->Args({1000000, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PoissonDiskOneRadius)->Args({100000, 1})->Args({100000, 2})->Args({1000000, 1})->Args({1000000, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MedialAxisLeaf)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MedialAxisWavyStrip)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
