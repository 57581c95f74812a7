// Initial synthesis of structurally-sound-patterns.md on the bunny (paper Table 1: bunny at 256^3,
// t_init 1.1 s; Table 2: 8-45 s for the whole loop). Counters: shell voxels, levels, seconds of
// the finest levels, candidates per second; the voxelization and the pyramid are timed apart.
#include <benchmark/benchmark.h>

#include <fabsynth/io/image.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/surface_pattern.hpp>

#include <chrono>
#include <string>

using namespace fabsynth;
namespace sp = fabsynth::surface_pattern;

namespace {

const triangle_mesh& bunny() {
    static const triangle_mesh m = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny.obj");
    return m;
}

sp::exemplar hooks() {
    return sp::make_exemplar(io::read_png(std::string(FABSYNTH_DATA_DIR) + "/exemplars/hooks.png"), nullptr, {.feature_px = 6});
}

// Arg: resolution (256: 8 levels, 512: 9 levels).
void BM_SurfaceShell(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    std::size_t voxels = 0;
    for (auto _ : state) {
        const sp::surface_shell s = sp::make_shell(bunny(), {.size_mm = 100, .resolution = n});
        const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, sp::default_levels(n));
        voxels = s.size();
        benchmark::DoNotOptimize(pyr.levels.size());
    }
    state.counters["voxels"] = static_cast<double>(voxels);
}
BENCHMARK(BM_SurfaceShell)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_InitialSynthesis(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    const sp::surface_shell s = sp::make_shell(bunny(), {.size_mm = 100, .resolution = n});
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, sp::default_levels(n));
    const sp::exemplar ex = hooks();
    sp::synthesis_result r;
    double setup = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const sp::synthesizer syn(pyr, ex, {.up = vec3(0, 1, 0), .seed = 1});  // stack + neighbourhoods, timed in the total
        setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r = syn.synthesize();
        benchmark::DoNotOptimize(r.solid.data());
    }
    state.counters["setup_s"] = setup;
    state.counters["synthesize_s"] = r.seconds;
    double candidates = 0, seconds = 0;
    for (const sp::level_report& l : r.levels) candidates += static_cast<double>(l.candidates), seconds += l.seconds;
    state.counters["voxels"] = static_cast<double>(s.size());
    state.counters["levels"] = static_cast<double>(pyr.levels.size());
    state.counters["level0_s"] = r.levels[0].seconds;
    state.counters["level1_s"] = r.levels[1].seconds;
    state.counters["level2_s"] = r.levels[2].seconds;
    state.counters["candidates_per_s"] = candidates / seconds;
}
BENCHMARK(BM_InitialSynthesis)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
