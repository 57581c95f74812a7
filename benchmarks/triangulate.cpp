// Ear-clipping triangulation (geometry/triangulate.hpp) of every polygon of a bundled vector
// exemplar, as curve_patterns does before extrusion. Items = input vertices.
#include <benchmark/benchmark.h>

#include <string>

#include "fabsynth/geometry/triangulate.hpp"
#include "fabsynth/io/svg.hpp"
#include "fabsynth/vector_pattern/exemplar.hpp"

namespace {

void BM_TriangulateExemplar(benchmark::State& state, const char* file) {
    const auto ex = fabsynth::vector_pattern::exemplar_from_svg(fabsynth::io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/" + file));
    std::size_t vertices = 0;
    for (const auto& p : ex.polygons) {
        vertices += p.outer.size();
        for (const auto& h : p.holes) vertices += h.size();
    }
    for (auto _ : state)
        for (const auto& p : ex.polygons) benchmark::DoNotOptimize(fabsynth::triangulate(p));
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * vertices));
    state.counters["holes"] = static_cast<double>(ex.holes());
}

}  // namespace

BENCHMARK_CAPTURE(BM_TriangulateExemplar, lace_scallop, "lace_scallop.svg")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TriangulateExemplar, vine, "vine.svg")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TriangulateExemplar, quatrefoil, "quatrefoil.svg")->Unit(benchmark::kMillisecond);
