// Surface blocks of the 3D filigree pipeline. Local parameterizations (surface/exponential_map.hpp)
// on the full-resolution bunny scaled to a 100 mm bounding box: the per-mesh set-up (adjacency,
// normals, incidence) and one discrete exponential map of a patch of radius 10 or 20 mm
// (filigree-synthesis.md §8.1 computes matching, overlap and deformation on such patches; Table 3
// finds them the dominant 3D cost). The printable solid of §6.2 (surface/offset.hpp): an
// open cylinder band (a vase wall, r 30 mm, 60 mm high, 0.5 mm edges) thickened to 1.2 mm.
// Filigree synthesis on surfaces (filigree-synthesis.md Table 3): the bundled vase (scripts/make_vase.py,
// 6.0 k vertices) and the bunny (36 k vertices, 100 mm), c_scroll elements of 14 / 16 mm, 0.8 mm strips:
// synthesis (initialization, placement, boosting through local parameterizations), then baking and
// the structural optimization of §5; counters give the instances and the time spent building maps.
//   bench_surface --benchmark_filter=Patch
#include <benchmark/benchmark.h>

#include <fabsynth/core/rng.hpp>
#include <fabsynth/filigree/surface/structure.hpp>
#include <fabsynth/io/svg.hpp>
#include <fabsynth/surface/exponential_map.hpp>
#include <fabsynth/surface/offset.hpp>
#include <fabsynth/io/mesh.hpp>

#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

namespace {

using namespace fabsynth;

const triangle_mesh& bunny() {
    static const triangle_mesh m = [] {
        triangle_mesh b = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/bunny.obj");
        fit_to_size(b, 100.0);
        return b;
    }();
    return m;
}

void BM_ExponentialMapSetup(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(surface_patcher(bunny()));
    state.counters["vertices"] = static_cast<double>(bunny().num_vertices());
}
BENCHMARK(BM_ExponentialMapSetup)->Unit(benchmark::kMillisecond);

void BM_ExponentialMapPatch(benchmark::State& state) {
    const surface_patcher patcher(bunny());
    const double radius = static_cast<double>(state.range(0));
    counter_rng rng(5);
    std::size_t verts = 0, patches = 0;
    for (auto _ : state) {
        const auto face = static_cast<std::uint32_t>(rng.uniform_int(bunny().num_faces()));
        const vec3 n = patcher.face_normal(face);
        const vec3 up = std::abs(n.y) < 0.9 ? vec3(0, 1, 0) : vec3(1, 0, 0);
        const local_patch p = patcher.patch({face, {1.0 / 3, 1.0 / 3, 1.0 / 3}}, up, radius);
        verts += p.vertices.size(), ++patches;
        benchmark::DoNotOptimize(p.uv.data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(patches));
    state.counters["patch_vertices"] = patches ? static_cast<double>(verts) / static_cast<double>(patches) : 0.0;
}
BENCHMARK(BM_ExponentialMapPatch)->Arg(10)->Arg(20)->Unit(benchmark::kMillisecond);

void BM_ThickenSurface(benchmark::State& state) {
    triangle_mesh band;  // open cylinder, 376 segments around (0.5 mm), rings every 0.5 mm
    const int around = 376, rings = 120;
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i < around; ++i) {
            const double a = 2 * std::numbers::pi * i / around;
            band.vertices.emplace_back(30 * std::cos(a), 30 * std::sin(a), 0.5 * j);
        }
    auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * around + i % around); };
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < around; ++i) band.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)}), band.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    const double cell = static_cast<double>(state.range(0)) / 100.0;
    std::size_t tris = 0;
    for (auto _ : state) tris = thicken_surface(band, 1.2, {.cell = cell}).num_faces();
    state.counters["cell_mm"] = cell;
    state.counters["band_faces"] = static_cast<double>(band.num_faces());
    state.counters["solid_faces"] = static_cast<double>(tris);
}
BENCHMARK(BM_ThickenSurface)->Arg(30)->Arg(15)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_FiligreeOnSurface(benchmark::State& state) {
    const bool on_bunny = state.range(0) == 1;
    const triangle_mesh& base = on_bunny ? bunny() : [] () -> const triangle_mesh& {
        static const triangle_mesh v = io::read_mesh(std::string(FABSYNTH_DATA_DIR) + "/meshes/vase.obj");
        return v;
    }();
    filigree::element_options eo;
    eo.size_mm = on_bunny ? 16 : 14, eo.width_mm = 0.8, eo.name = "c_scroll";
    const std::vector<filigree::element> cls{
        filigree::element_from_svg(io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/filigree/c_scroll.svg", 0.01), eo)};
    const std::vector<double> w{1.0};
    const surface_patcher patcher(base);
    const auto region = filigree::surface_region::whole(patcher);
    const vec3 up = on_bunny ? vec3(0, 1, 0) : vec3(0, 0, 1);
    const auto direction = filigree::surface_direction_field::from_up_vector(patcher, up);
    const auto scale = filigree::surface_scale_field::constant(base, 1.0);
    const filigree::surface_control field{&direction, &scale};
    filigree::synthesis_options so;
    filigree::surface_synthesis_result syn;
    double synthesis = 0, structure = 0;
    for (auto _ : state) {
        auto t = std::chrono::steady_clock::now();
        syn = filigree::synthesize_on_surface(cls, w, region, field, so);
        synthesis = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
        t = std::chrono::steady_clock::now();
        filigree::surface_reinforcement_options ro;
        ro.up = up;
        benchmark::DoNotOptimize(filigree::reinforce_on_surface(cls, w, region, field, so, syn, ro));
        structure = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    }
    state.counters["vertices"] = static_cast<double>(base.num_vertices());
    state.counters["instances"] = static_cast<double>(syn.instances.size());
    state.counters["synthesis_s"] = synthesis;
    state.counters["structure_s"] = structure;
    state.counters["maps"] = static_cast<double>(syn.maps_built);
    state.counters["map_s_summed"] = syn.map_seconds;
}
BENCHMARK(BM_FiligreeOnSurface)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
