// SVG parsing/writing and 2D polygon predicates on the bundled vector exemplars.
#include <benchmark/benchmark.h>

#include <fabsynth/geometry/polygon.hpp>
#include <fabsynth/io/svg.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace {

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

const std::string lace_path = std::string(FABSYNTH_DATA_DIR) + "/vector/lace_scallop.svg";

void BM_SvgParseLace(benchmark::State& state) {
    const std::string text = slurp(lace_path);
    for (auto _ : state) benchmark::DoNotOptimize(fabsynth::io::parse_svg(text, "lace_scallop.svg"));
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text.size()));
}
BENCHMARK(BM_SvgParseLace)->Unit(benchmark::kMillisecond);

void BM_SvgWriteLace(benchmark::State& state) {
    const auto doc = fabsynth::io::parse_svg(slurp(lace_path), "lace_scallop.svg");
    for (auto _ : state) benchmark::DoNotOptimize(fabsynth::io::to_svg_string(doc));
}
BENCHMARK(BM_SvgWriteLace)->Unit(benchmark::kMillisecond);

void BM_PolygonIsSimpleLace(benchmark::State& state) {
    const auto doc = fabsynth::io::parse_svg(slurp(lace_path), "lace_scallop.svg");
    std::size_t edges = 0;
    for (const auto& s : doc.shapes)
        for (const auto& r : s.rings()) edges += r.size();
    for (auto _ : state)
        for (const auto& s : doc.shapes)
            for (const auto& r : s.rings()) benchmark::DoNotOptimize(fabsynth::is_simple(r));
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * edges));
}
BENCHMARK(BM_PolygonIsSimpleLace)->Unit(benchmark::kMillisecond);

void BM_PolygonGroupRingsLace(benchmark::State& state) {
    const auto doc = fabsynth::io::parse_svg(slurp(lace_path), "lace_scallop.svg");
    std::vector<fabsynth::ring2> rings;
    for (const auto& s : doc.shapes)
        for (const auto& r : s.rings()) rings.push_back(r);
    for (auto _ : state) benchmark::DoNotOptimize(fabsynth::group_rings(rings));
}
BENCHMARK(BM_PolygonGroupRingsLace)->Unit(benchmark::kMillisecond);

// The outline of a band along an Archimedean spiral with N points per side: every edge overlaps
// many others in x and in y (the case that made an x-sweep quadratic, issue 16).
void BM_PolygonIsSimpleSpiral(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    fabsynth::ring2 outline;
    for (std::size_t i = 0; i < n; ++i) {
        const double t = 1.0 + 0.01 * static_cast<double>(i);
        outline.emplace_back((t + 0.5) * std::cos(t), (t + 0.5) * std::sin(t));
    }
    for (std::size_t i = n; i-- > 0;) {
        const double t = 1.0 + 0.01 * static_cast<double>(i);
        outline.emplace_back((t - 0.5) * std::cos(t), (t - 0.5) * std::sin(t));
    }
    for (auto _ : state) benchmark::DoNotOptimize(fabsynth::is_simple(outline));
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * outline.size()));
}
BENCHMARK(BM_PolygonIsSimpleSpiral)->Arg(10000)->Arg(40000)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace
