// Synthesis along a band (vector_pattern/synthesis.hpp), the paper's Table 1 (Zhou et al. 2014, §6.1):
// per case, the DP time and its peak memory, with the number of input pieces (default Reeb slicing)
// and of result pieces. Target lengths are chosen from the mean piece width so that results hold
// about 60-190 pieces, the range of Table 1. Constraints: one component for single-component
// exemplars (as the paper's lamp curves), none for the others; autocorrelation penalty beta = 1
// (Table 1: "all results use the auto-correlation penalty"). Closed cases search a cycle.
//
// Counters: dp_s (DP seconds, mean per iteration), dp_peak_MB (table + layer hash tables + descriptor
// memo), dp_entries, input_pieces, result_pieces, total time per iteration (slicing, DP, offsets,
// stitching, contours, validation) is the benchmark time.
#include <benchmark/benchmark.h>

#include <fabsynth/io/svg.hpp>
#include <fabsynth/vector_pattern.hpp>

#include <string>

namespace {

struct bench_case {
    const char* file;
    bool closed;
    double result_pieces;  // wanted result size (L = this * mean piece width)
};

const bench_case cases[] = {
    {"greek_key.svg", false, 60},  {"zigzag.svg", false, 75},      {"hearts.svg", false, 110},
    {"quatrefoil.svg", true, 70},  {"greek_key.svg", true, 150},   {"lace_scallop.svg", false, 100},
    {"pearls.svg", false, 130},    {"vine.svg", true, 65},         {"zigzag.svg", true, 190},
};

void BM_synthesize_along(benchmark::State& st) {
    const bench_case& c = cases[st.range(0)];
    const auto ex = fabsynth::vector_pattern::exemplar_from_svg(fabsynth::io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/" + c.file));
    st.SetLabel(std::string(c.file) + (c.closed ? " closed" : " open"));
    fabsynth::vector_pattern::synthesis_options o;
    o.closed = c.closed;
    o.beta = 1.0;
    if (ex.components() == 1) o.components = 1;
    // Mean piece width of the default slicing fixes L.
    const std::size_t n = fabsynth::vector_pattern::detail::choose_cuts(ex, o).size() + 1;
    o.length = c.result_pieces * ex.width() / static_cast<double>(n);
    double dp = 0, iterations = 0;
    fabsynth::vector_pattern::synthesis_result r;
    for (auto _ : st) {
        try {
            r = fabsynth::vector_pattern::synthesize_along(ex, o);
        } catch (const fabsynth::error& e) {
            st.SkipWithError(e.what());
            return;
        }
        dp += r.dp_seconds;
        iterations += 1;
    }
    st.counters["dp_s"] = dp / iterations;
    st.counters["dp_peak_MB"] = static_cast<double>(r.dp_peak_bytes) / 1e6;
    st.counters["dp_entries"] = static_cast<double>(r.dp_entries);
    st.counters["input_pieces"] = static_cast<double>(r.input_pieces);
    st.counters["result_pieces"] = static_cast<double>(r.sequence.size());
    st.counters["length"] = o.length;
}

// Long bands: the Greek key along a line of 100 to 3200 band heights (result pieces ~8 per
// height), the whole synthesis; the growth with the length was quadratic in the final merge
// (merge_contours) before its unions were made a tree.
void BM_synthesize_long_band(benchmark::State& st) {
    const auto ex = fabsynth::vector_pattern::exemplar_from_svg(fabsynth::io::read_svg(std::string(FABSYNTH_DATA_DIR) + "/vector/greek_key.svg"));
    fabsynth::vector_pattern::synthesis_options o;
    o.length = static_cast<double>(st.range(0)) * ex.height();
    fabsynth::vector_pattern::synthesis_result r;
    for (auto _ : st) r = fabsynth::vector_pattern::synthesize_along(ex, o);
    st.counters["heights"] = static_cast<double>(st.range(0));
    st.counters["result_pieces"] = static_cast<double>(r.sequence.size());
    st.counters["dp_s"] = r.dp_seconds;
}

}  // namespace

BENCHMARK(BM_synthesize_long_band)->RangeMultiplier(2)->Range(100, 3200)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_synthesize_along)->DenseRange(0, static_cast<int>(std::size(cases)) - 1)->Unit(benchmark::kMillisecond)->Iterations(2);
