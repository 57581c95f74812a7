// Bands on surfaces (topology-constrained-vector-patterns.md §6.3): the bundled vase's harmonic
// parameterization, a curve through 8 points around its belly, and a band of separate disks (12 mm)
// embossed onto (1 mm above a 2 mm shell) or carved out of (2.5 mm shell) the vase, at grid cells of
// 0.5, 0.4 and 0.25 mm.
#include <benchmark/benchmark.h>

#include <fabsynth/surface/disk_parameterization.hpp>
#include <fabsynth/surface/curve.hpp>
#include <fabsynth/surface/decoration.hpp>
#include <fabsynth/io/mesh.hpp>
#include <fabsynth/io/svg.hpp>
#include <fabsynth/vector_pattern/exemplar.hpp>
#include <fabsynth/vector_pattern/synthesis.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

using namespace fabsynth;

namespace {

triangle_mesh vase() { return io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/vase.obj"); }

std::vector<vec3> belly_loop() {
    std::vector<vec3> p;
    for (int i = 0; i < 8; ++i) {
        const double a = 2 * std::numbers::pi * i / 8, z = 45 + 6 * std::sin(2 * a), r = 20 + 9 * std::sin(std::numbers::pi * z / 70);
        p.push_back({r * std::cos(a), r * std::sin(a), z});
    }
    return p;
}

void BM_DiskParameterizationVase(benchmark::State& state) {
    const triangle_mesh m = vase();
    for (auto _ : state) {
        const disk_parameterization phi(m);
        benchmark::DoNotOptimize(phi.domain_vertices().data());
    }
    state.counters["faces"] = static_cast<double>(m.faces.size());
}
BENCHMARK(BM_DiskParameterizationVase)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SurfaceCurveVase(benchmark::State& state) {
    const disk_parameterization phi(vase());
    const std::vector<vec3> loop = belly_loop();
    std::size_t points = 0;
    for (auto _ : state) {
        const surface_curve s = trace_surface_curve(phi, loop, true);
        points = s.points.size();
        benchmark::DoNotOptimize(s.normals.data());
    }
    state.counters["points"] = static_cast<double>(points);
}
BENCHMARK(BM_SurfaceCurveVase)->Unit(benchmark::kMillisecond)->UseRealTime();

// Arg 0: 0 emboss, 1 carve; arg 1: cell in 1/100 mm.
void BM_DecorateVase(benchmark::State& state) {
    const triangle_mesh m = vase();
    const disk_parameterization phi(m);
    const space_curve band = trace_surface_curve(phi, belly_loop(), true).band_curve(1.5);
    const auto raw = vector_pattern::exemplar_from_svg(io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/disks.svg"));
    const auto ex = vector_pattern::scaled(raw, 12.0 / raw.height());
    vector_pattern::synthesis_options so;
    so.band_height = 12.0;
    so.length = band.length();
    so.closed = true;
    const auto pattern = vector_pattern::synthesize_along(ex, so).polygons;
    surface_decoration_options o;
    o.mode = state.range(0) == 0 ? decoration_mode::emboss : decoration_mode::carve;
    o.shell = state.range(0) == 0 ? 2.0 : 2.5;
    o.height = 1.0;
    o.cell = static_cast<double>(state.range(1)) / 100.0;
    std::size_t faces = 0;
    for (auto _ : state) {
        const triangle_mesh out = decorate_surface(m, band, pattern, o);
        faces = out.faces.size();
        benchmark::DoNotOptimize(out.vertices.data());
    }
    state.counters["triangles"] = static_cast<double>(faces);
}
BENCHMARK(BM_DecorateVase)->Args({0, 50})->Args({0, 40})->Args({0, 25})->Args({1, 40})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
