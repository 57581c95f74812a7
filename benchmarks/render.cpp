// The preview renderer (geometry/render.hpp) on large meshes: a torus of n x n/2 quads at
// 1024 x 1024 with 2x2 supersampling.
#include <benchmark/benchmark.h>

#include <fabsynth/geometry/render.hpp>

#include <cmath>
#include <numbers>

using namespace fabsynth;

namespace {

triangle_mesh torus(int nu, int nv) {
    triangle_mesh m;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
            m.vertices.push_back({(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
        }
    const auto id = [&](int i, int j) { return static_cast<std::uint32_t>((i % nu) * nv + (j % nv)); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return m;
}

// Arg: quads along the big circle (triangles = arg^2).
void BM_RenderShaded(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    const triangle_mesh m = torus(n, n / 2);
    for (auto _ : state) {
        const image8 im = render_shaded(m, {.direction = {1, 2, -3}, .up = {0, 0, 1}}, {.width = 1024, .height = 1024});
        benchmark::DoNotOptimize(im.data.data());
    }
    state.counters["triangles"] = static_cast<double>(m.num_faces());
}
BENCHMARK(BM_RenderShaded)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
