// Voxelization and marching-cubes throughput.
//   bench_voxel --benchmark_filter=Surface
#include <benchmark/benchmark.h>

#include <fabsynth/geometry/marching_cubes.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/voxel.hpp>

#include <string>

namespace {

const fabsynth::triangle_mesh& bunny() {
    static const fabsynth::triangle_mesh m = fabsynth::io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny_lowres.obj");
    return m;
}

void BM_VoxelizeSurface(benchmark::State& state) {
    const auto& m = bunny();
    const int res = static_cast<int>(state.range(0));
    std::uint64_t voxels = 0;
    for (auto _ : state) {
        auto shell = fabsynth::voxelize_surface(m, res);
        voxels = shell.storage().stored();
        benchmark::DoNotOptimize(shell);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(m.num_faces()));  // triangles/s
    state.counters["shell_voxels"] = static_cast<double>(voxels);
}
BENCHMARK(BM_VoxelizeSurface)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);

void BM_VoxelizeSolid(benchmark::State& state) {
    const auto& m = bunny();
    const auto g = fabsynth::fit_grid(fabsynth::bounding_box(m), static_cast<int>(state.range(0)), 1);
    for (auto _ : state) {
        auto solid = fabsynth::voxelize_solid(m, g);
        benchmark::DoNotOptimize(solid);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(g.count()));  // voxels/s
}
BENCHMARK(BM_VoxelizeSolid)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);

void BM_MarchingCubesSphere(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    const double h = 1.0 / n;
    auto f = [h](fabsynth::ivec3 p) { return glm::length(fabsynth::vec3(p) * h - 0.5) - 0.4; };
    std::size_t faces = 0;
    for (auto _ : state) {
        auto m = fabsynth::marching_cubes(f, fabsynth::ivec3(n + 1), fabsynth::vec3(0), fabsynth::vec3(h));
        faces = m.num_faces();
        benchmark::DoNotOptimize(m);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n) * n * n);  // cubes/s
    state.counters["faces"] = static_cast<double>(faces);
}
BENCHMARK(BM_MarchingCubesSphere)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);

void BM_LabelComponents26(benchmark::State& state) {
    const auto shell = fabsynth::voxelize_surface(bunny(), static_cast<int>(state.range(0)));
    for (auto _ : state) {
        auto cc = fabsynth::label_components<fabsynth::connectivity::c26>(shell, [](const fabsynth::shell_voxel& v) {
            return v.normal != fabsynth::vec3(0);
        });
        benchmark::DoNotOptimize(cc);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(shell.storage().stored()));
}
BENCHMARK(BM_LabelComponents26)->Arg(256)->Unit(benchmark::kMillisecond);

}  // namespace
