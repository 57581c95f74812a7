// Mesh simplification with guarantees (geometry/simplify.hpp) on a 2 M-triangle level set, the
// size of the main job's meshes (issue "Print-ready meshes"): the decimation alone, each check
// alone, and the whole call at half a voxel.
//
// The surface: a gyroid sheet (genus 246, curved everywhere: no flat stretch to make the checks
// cheap) clipped to a sphere of radius 27.5 mm, extracted by marching tetrahedra at a 0.39 mm
// grid (the surface-pattern bunny's voxel): 2.05 M triangles; tolerance 0.195 mm.
#include <benchmark/benchmark.h>

#include <fabsynth/geometry/hausdorff.hpp>
#include <fabsynth/geometry/marching_cubes.hpp>
#include <fabsynth/geometry/mesh_topology.hpp>
#include <fabsynth/geometry/self_intersection.hpp>
#include <fabsynth/geometry/simplify.hpp>

#include <cmath>

using namespace fabsynth;

namespace {

constexpr double voxel = 0.39, tolerance = voxel / 2;

const triangle_mesh& level_set() {
    static const triangle_mesh m = [] {
        const int n = 147;
        const vec3 origin(-28.5);
        const auto f = [&](ivec3 i) {
            const vec3 p = origin + vec3(i) * voxel;
            const double k = 2 * 3.14159265358979 / 16.0;  // 16 mm period
            const double g = std::sin(k * p.x) * std::cos(k * p.y) + std::sin(k * p.y) * std::cos(k * p.z) + std::sin(k * p.z) * std::cos(k * p.x);
            const double sheet = std::abs(g) - 0.35;  // a thickened sheet, about 1.5 mm thick
            return std::max(sheet, glm::length(p) - 27.5);
        };
        return marching_cubes(f, {n, n, n}, origin, vec3(voxel));
    }();
    return m;
}

void BM_SimplifyDecimation(benchmark::State& state) {
    const triangle_mesh& m = level_set();
    std::size_t faces = 0;
    for (auto _ : state) faces = detail::simplify::collapser(m).run(detail::simplify::cost_limit * tolerance, detail::simplify::tracked_bound * tolerance).faces.size();
    state.counters["raw_triangles"] = static_cast<double>(m.faces.size());
    state.counters["triangles"] = static_cast<double>(faces);
}
BENCHMARK(BM_SimplifyDecimation)->Unit(benchmark::kSecond)->Iterations(1);

void BM_SimplifyCheckSelfIntersections(benchmark::State& state) {
    const triangle_mesh s = detail::simplify::collapser(level_set()).run(detail::simplify::cost_limit * tolerance, detail::simplify::tracked_bound * tolerance);
    for (auto _ : state) benchmark::DoNotOptimize(find_self_intersections(s).pairs);
}
BENCHMARK(BM_SimplifyCheckSelfIntersections)->Unit(benchmark::kSecond)->Iterations(1);

void BM_SimplifyCheckHausdorff(benchmark::State& state) {
    const triangle_mesh s = detail::simplify::collapser(level_set()).run(detail::simplify::cost_limit * tolerance, detail::simplify::tracked_bound * tolerance);
    hausdorff_interval h;
    for (auto _ : state)
        h = hausdorff_distance(level_set(), s, {.precision = tolerance / 8, .stop_below = tolerance, .abort_above = tolerance});
    state.counters["hausdorff_upper_mm"] = h.upper;
}
BENCHMARK(BM_SimplifyCheckHausdorff)->Unit(benchmark::kSecond)->Iterations(1);

void BM_SimplifyMesh(benchmark::State& state) {
    const triangle_mesh& m = level_set();
    simplify_report rep;
    for (auto _ : state) benchmark::DoNotOptimize(simplify_mesh(m, {.tolerance = tolerance}, &rep).faces.size());
    state.counters["raw_triangles"] = static_cast<double>(rep.raw_faces);
    state.counters["triangles"] = static_cast<double>(rep.faces);
    state.counters["attempts"] = rep.attempts;
    state.counters["simplified"] = rep.simplified;
    state.counters["hausdorff_mm"] = rep.hausdorff.upper;
    state.counters["genus"] = static_cast<double>(analyze_topology(m).genus);
}
BENCHMARK(BM_SimplifyMesh)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
