// Vector-pattern exemplars and slicing (vector_pattern/*.hpp): time to build an exemplar from a parsed SVG
// (validation + Clipper union), to slice it into pieces with portals (uniform, 8 pieces), and to
// run the Reeb sweep (default raster max(W, H)/1024). Counters: vertices, pieces, portals, cuts.
#include <benchmark/benchmark.h>

#include <fabsynth/geometry/clip.hpp>
#include <fabsynth/io/svg.hpp>
#include <fabsynth/vector_pattern.hpp>

#include <string>

namespace {

const char* const files[] = {"zigzag.svg", "greek_key.svg", "hearts.svg", "pearls.svg", "quatrefoil.svg", "vine.svg",
                             "lace_scallop.svg"};

fabsynth::io::svg_document doc_of(int i) {
    return fabsynth::io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/" + files[i]);
}

double vertices(const fabsynth::vector_pattern::exemplar& ex) {
    double v = 0;
    for (const auto& p : ex.polygons) {
        v += static_cast<double>(p.outer.size());
        for (const auto& h : p.holes) v += static_cast<double>(h.size());
    }
    return v;
}

void BM_make_exemplar(benchmark::State& st) {
    const auto doc = doc_of(static_cast<int>(st.range(0)));
    st.SetLabel(files[st.range(0)]);
    fabsynth::vector_pattern::exemplar ex;
    for (auto _ : st) benchmark::DoNotOptimize(ex = fabsynth::vector_pattern::exemplar_from_svg(doc));
    st.counters["vertices"] = vertices(ex);
}

void BM_slice_uniform(benchmark::State& st) {
    const auto ex = fabsynth::vector_pattern::exemplar_from_svg(doc_of(static_cast<int>(st.range(0))));
    st.SetLabel(files[st.range(0)]);
    const auto cuts = fabsynth::vector_pattern::uniform_cuts(ex, 7);
    std::vector<fabsynth::vector_pattern::piece> pieces;
    for (auto _ : st) benchmark::DoNotOptimize(pieces = fabsynth::vector_pattern::slice(ex, cuts));
    double portals = 0;
    for (const auto& p : pieces) portals += static_cast<double>(p.left.size() + p.right.size());
    st.counters["vertices"] = vertices(ex);
    st.counters["pieces"] = static_cast<double>(pieces.size());
    st.counters["portals"] = portals;
}

void BM_reeb(benchmark::State& st) {
    const auto ex = fabsynth::vector_pattern::exemplar_from_svg(doc_of(static_cast<int>(st.range(0))));
    st.SetLabel(files[st.range(0)]);
    fabsynth::vector_pattern::reeb_result r;
    for (auto _ : st) benchmark::DoNotOptimize(r = fabsynth::vector_pattern::reeb_slicing(ex, {.group_distance = 2.0}));
    st.counters["events"] = static_cast<double>(r.events.size());
    st.counters["cuts"] = static_cast<double>(r.cuts.size());
}

}  // namespace

BENCHMARK(BM_make_exemplar)->DenseRange(0, 6)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_slice_uniform)->DenseRange(0, 6)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_reeb)->DenseRange(0, 6)->Unit(benchmark::kMillisecond);
