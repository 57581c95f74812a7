// structurally-sound-patterns.md on the bunny (paper Table 1: bunny at 256^3, t_init 1.1 s, 11-76 s
// in total; Table 2: structural analysis 4.6-27 s). BM_InitialSynthesis: shell voxels, levels,
// seconds of the finest levels, candidates per second (voxelization and pyramid timed apart).
// BM_StructuralLoop: the whole Algorithm 1 after the initial synthesis, split into structural
// analysis and resynthesis, with iterations, solves and seconds per solve.
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

// Arg: resolution. The hooks exemplar at one voxel per pixel (r_pattern 6 px), gravity along -y
// (the bunny is y-up), the paper's 1000 samples, ABS.
void BM_StructuralLoop(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    const sp::surface_shell s = sp::make_shell(bunny(), {.size_mm = 100, .resolution = n});
    const sp::shell_pyramid pyr = sp::build_shell_pyramid(s, sp::default_levels(n));
    const sp::synthesizer syn(pyr, hooks(), {.up = vec3(0, 1, 0), .seed = 1});
    const sp::shell_level& l0 = pyr.levels[0];
    sp::synthesis_result initial = syn.synthesize();
    (void)sp::remove_specks(l0.geometry, l0.voxels, initial.solid, 1.2);
    sp::structure_options so;
    so.r_pattern_mm = 6 * syn.options().mm_per_px;
    so.thickness_mm = 1.2;
    so.gravity = {0, -1, 0};
    sp::structure_report rep;
    double graph_s = 0;
    for (auto _ : state) {
        sp::synthesis_result r = initial;
        const auto t0 = std::chrono::steady_clock::now();
        const sp::surface_graph gs = sp::build_surface_graph(l0);
        graph_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        rep = sp::optimize_structure(syn, r, gs, so);
        benchmark::DoNotOptimize(r.solid.data());
    }
    double solve_s = 0;
    int solves = 0;
    for (const sp::structural_step_report& it : rep.iterations) solve_s += it.solve_seconds, solves += it.solves;
    state.counters["voxels"] = static_cast<double>(l0.size());
    state.counters["iterations"] = static_cast<double>(rep.iterations.size());
    state.counters["converged"] = rep.converged ? 1 : 0;
    state.counters["solves"] = solves;
    state.counters["s_per_solve"] = solves ? solve_s / solves : 0.0;
    state.counters["surface_graph_s"] = graph_s;
    state.counters["structure_s"] = rep.structure_seconds;
    state.counters["resynthesis_s"] = rep.resynthesis_seconds;
    state.counters["initial_synthesis_s"] = initial.seconds;
}
BENCHMARK(BM_StructuralLoop)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// §6.3 validation of the full-solid bunny shell (every shell voxel solid, thickened inward by
// 1.2 mm, 100 mm, ABS, gravity -y, the bottom 10% clamped): one load case of the sparse voxel FEM.
// Arg: resolution. Run alone (--benchmark_filter=ValidateFullShell) for the peak of this case.
void BM_ValidateFullShell(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    const sp::surface_shell s = sp::make_shell(bunny(), {.size_mm = 100, .resolution = n});
    const std::vector<std::uint8_t> all(s.size(), 1);
    const sp::voxel_set thick = sp::thicken_inward(s.geometry, s.voxels, s.normals, all, 1.2);
    sp::validation_options vo;
    vo.gravity = {0, -1, 0};
    sp::stress_statistics st;
    for (auto _ : state) {
        st = sp::validate_stress(thick, vo);
        benchmark::DoNotOptimize(st.p99);
    }
    state.counters["voxels"] = static_cast<double>(thick.size());
    state.counters["dofs"] = static_cast<double>(st.dofs);
    state.counters["iterations"] = st.iterations;
    state.counters["p99_Pa"] = st.p99;
    state.counters["validate_s"] = st.seconds;
}
BENCHMARK(BM_ValidateFullShell)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
