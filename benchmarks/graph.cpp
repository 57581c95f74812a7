// Graph block on a voxelized sphere shell (the G_surface of structurally-sound-patterns.md §5.1):
// building the 26-neighbour graph, and CONNECTSAMPLES' core (Algorithm 5): a Dijkstra forest from
// ~1000 samples in G_solid, the solid adjacency, the forest extended to G_surface and the empty
// adjacency (pairs already solid skipped). The solid mask is a hashed stripe pattern (about 60% of
// the voxels) so both passes find edges.
//   bench_graph --benchmark_filter=ConnectSamples
#include <benchmark/benchmark.h>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/graph.hpp>

#include <cmath>
#include <map>
#include <vector>

namespace {

using namespace fabsynth;

/// Voxels of a (2R+4)^3 grid whose centre is within [R - 1, R + 1] voxels of the grid centre.
const std::pair<grid_geometry, std::vector<ivec3>>& shell(int radius) {
    static std::map<int, std::pair<grid_geometry, std::vector<ivec3>>> cache;
    auto it = cache.find(radius);
    if (it != cache.end()) return it->second;
    const int n = 2 * radius + 4;
    grid_geometry g{ivec3(n), vec3(0.0), vec3(0.25)};
    std::vector<ivec3> vox;
    const double c = 0.5 * n, lo = radius - 1.0, hi = radius + 1.0;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double dx = i + 0.5 - c, dy = j + 0.5 - c, dz = k + 0.5 - c;
                const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
                if (d >= lo && d <= hi) vox.push_back({i, j, k});
            }
    return cache.emplace(radius, std::make_pair(g, std::move(vox))).first->second;
}

void BM_FromVoxelsShell(benchmark::State& state) {
    const auto& [g, vox] = shell(static_cast<int>(state.range(0)));
    std::size_t arcs = 0;
    for (auto _ : state) {
        auto vg = graph::from_voxels(g, vox);
        arcs = vg.graph.num_arcs();
        benchmark::DoNotOptimize(vg);
    }
    state.counters["voxels"] = static_cast<double>(vox.size());
    state.counters["arcs"] = static_cast<double>(arcs);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(vox.size()));
}
BENCHMARK(BM_FromVoxelsShell)->Arg(64)->Arg(200)->Unit(benchmark::kMillisecond);

void BM_ConnectSamplesShell(benchmark::State& state) {
    const auto& [g, vox] = shell(static_cast<int>(state.range(0)));
    const auto vg = graph::from_voxels(g, vox);
    const std::size_t n = vg.size();
    std::vector<std::uint8_t> solid(n);
    for (std::size_t v = 0; v < n; ++v) {
        const ivec3 p = vg.voxels[v];
        solid[v] = ((p.x / 6 + p.y / 6 + p.z / 9) % 3 != 0) || hash_uniform(7, p.x, p.y, p.z) < 0.1 ? 1 : 0;
    }
    std::vector<graph::vertex_id> samples;  // ~1000 solid samples, evenly spread in vertex order
    for (std::size_t v = 0; v < n && samples.size() < 1000; v += n / 1000)
        if (solid[v]) samples.push_back(static_cast<graph::vertex_id>(v));
    std::size_t solid_pairs = 0, empty_pairs = 0, path_vertices = 0;
    for (auto _ : state) {
        const auto forest = graph::dijkstra_forest(vg.graph, samples, solid);
        const auto solid_edges = graph::forest_adjacency(vg.graph, forest, solid);
        const auto grown = graph::extend_forest(vg.graph, forest);
        const auto empty_edges = graph::forest_adjacency(vg.graph, grown, {}, {.skip = solid_edges});
        solid_pairs = solid_edges.size(), empty_pairs = empty_edges.size();
        path_vertices = 0;
        for (const auto& e : empty_edges) path_vertices += e.path.size();
        benchmark::DoNotOptimize(empty_edges);
    }
    state.counters["voxels"] = static_cast<double>(n);
    state.counters["samples"] = static_cast<double>(samples.size());
    state.counters["solid_pairs"] = static_cast<double>(solid_pairs);
    state.counters["empty_pairs"] = static_cast<double>(empty_pairs);
    state.counters["empty_path_voxels"] = static_cast<double>(path_vertices);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
}
BENCHMARK(BM_ConnectSamplesShell)->Arg(64)->Arg(200)->Unit(benchmark::kMillisecond);

void BM_DijkstraForestShell(benchmark::State& state) {
    const auto& [g, vox] = shell(static_cast<int>(state.range(0)));
    const auto vg = graph::from_voxels(g, vox);
    std::vector<graph::vertex_id> samples;
    for (std::size_t v = 0; v < vg.size() && samples.size() < 1000; v += vg.size() / 1000) samples.push_back(static_cast<graph::vertex_id>(v));
    for (auto _ : state) benchmark::DoNotOptimize(graph::dijkstra_forest(vg.graph, samples));
    state.counters["voxels"] = static_cast<double>(vg.size());
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(vg.size()));
}
BENCHMARK(BM_DijkstraForestShell)->Arg(64)->Arg(200)->Unit(benchmark::kMillisecond);

void BM_ForestAdjacencyShell(benchmark::State& state) {
    const auto& [g, vox] = shell(static_cast<int>(state.range(0)));
    const auto vg = graph::from_voxels(g, vox);
    std::vector<graph::vertex_id> samples;
    for (std::size_t v = 0; v < vg.size() && samples.size() < 1000; v += vg.size() / 1000) samples.push_back(static_cast<graph::vertex_id>(v));
    const auto forest = graph::dijkstra_forest(vg.graph, samples);
    std::size_t pairs = 0;
    for (auto _ : state) {
        auto adj = graph::forest_adjacency(vg.graph, forest);
        pairs = adj.size();
        benchmark::DoNotOptimize(adj);
    }
    state.counters["voxels"] = static_cast<double>(vg.size());
    state.counters["pairs"] = static_cast<double>(pairs);
}
BENCHMARK(BM_ForestAdjacencyShell)->Arg(64)->Arg(200)->Unit(benchmark::kMillisecond);

}  // namespace
